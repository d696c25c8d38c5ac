// A mass pulled by a spring whose anchor moves at speed vs, with a braking
// force that acts only in a discrete mode: braking is on once the mass has
// passed xb (a when-clause sets the mode) and the if-expression on the mode
// changes the right-hand side. pre() of the mode gives the number of switches.
model FrictionMode "Spring-driven mass with a mode-switched brake"
  parameter Real m = 1 "Mass (kg)";
  parameter Real k = 3 "Spring stiffness (N/m)";
  parameter Real vs = 1 "Anchor speed (m/s)";
  parameter Real xb = 0.8 "Position where the brake engages (m)";
  parameter Real Fb = 1.5 "Brake force (N)";
  parameter Real c = 0.4 "Damping (N s/m)";
  Real x(start = 0, fixed = true) "Position (m)";
  Real v(start = 0, fixed = true) "Velocity (m/s)";
  discrete Real braking(start = 0) "1 once past xb";
  Integer switches(start = 0) "Mode changes";
equation
  der(x) = v;
  m*der(v) = k*(vs*time - x) - c*v - (if braking > 0.5 then Fb else 0);
  when x > xb then
    braking = 1 - pre(braking);
    switches = pre(switches) + 1;
  end when;
end FrictionMode;
