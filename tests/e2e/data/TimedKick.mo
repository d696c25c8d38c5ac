// An oscillator kicked once at a time T that is a parameter: the event time
// moves with T, so d(x)/d(T) jumps at the kick. A second clause on the same
// condition shifts the position (two when-clauses at one instant), and a
// third fires in the event iteration on the discrete counter it sets.
model TimedKick "Oscillator with a kick at time T"
  parameter Real k = 4 "Stiffness (N/m)";
  parameter Real T = 0.7 "Kick time (s)";
  parameter Real J = 0.5 "Velocity kick (m/s)";
  parameter Real dx = 0.1 "Position shift at the kick (m)";
  Real x(start = 1, fixed = true) "Position (m)";
  Real v(start = 0, fixed = true) "Velocity (m/s)";
  Integer kicks(start = 0) "Number of kicks";
equation
  der(x) = v;
  der(v) = -k*x;
  when time >= T then
    reinit(v, pre(v) + J*x);
    kicks = pre(kicks) + 1;
  end when;
  when time >= T then
    reinit(x, x + dx);
  end when;
  when kicks >= 1 then
    reinit(v, 2*v);
  end when;
end TimedKick;
