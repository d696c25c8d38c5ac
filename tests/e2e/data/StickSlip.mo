// A mass on a spring with Coulomb friction, written with a discrete mode:
// mode = +1 sliding forwards, -1 sliding backwards, 0 stuck. Sliding, the
// friction force is -Fc*mode; stuck, it balances the other forces (so
// der(v) = 0). The mode changes when the velocity reverses (then the mass
// sticks if the other forces are within the static limit Fs, else slides
// back) or, when stuck, when the other forces exceed Fs (breakaway).
// An external force F steps from 0 to F1 at tF to break the mass loose again.
model StickSlip "Spring-mass with Coulomb friction and stiction"
  parameter Real m = 1 "Mass (kg)";
  parameter Real k = 10 "Spring stiffness (N/m)";
  parameter Real Fc = 1 "Sliding (Coulomb) friction force (N)";
  parameter Real Fs = 1 "Static friction limit (N)";
  parameter Real F1 = 2 "External force after tF (N)";
  parameter Real tF = 6 "Time of the force step (s)";
  parameter Real x0 = 1.05 "Initial position (m)";
  Real x(start = x0, fixed = true) "Position (m)";
  Real v(start = 0, fixed = true) "Velocity (m/s)";
  Real F "External force (N)";
  Real f "Friction force on the mass (N)";
  discrete Real mode(start = -1) "+1/-1 sliding forwards/backwards, 0 stuck";
equation
  F = if time < tF then 0 else F1;
  f = if mode == 0 then -(F - k*x) else -Fc*mode;
  der(x) = v;
  m*der(v) = F - k*x + f;
  when (mode <> 0 and mode*v < 0) or (mode == 0 and abs(F - k*x) > Fs) then
    mode = if abs(F - k*x) <= Fs then 0 else (if F - k*x > 0 then 1 else -1);
    reinit(v, 0);
  end when;
end StickSlip;
