// An inertia braked by Coulomb friction written with the equations of the
// MSL's Rotational.Interfaces.PartialFriction (3.2.2): the mode machine is
// made of equations outside when-clauses that read pre() (startForward,
// startBackward, locked, mode), which Modelica solves by event iteration.
// Driven by A*sin(omega*time): it sticks, breaks away forward, stops, sticks,
// breaks away backward... (tests/e2e/test_friction_modes.cpp has the exact
// piecewise solution).
model FrictionStateMachine
  parameter Real J = 1;
  parameter Real A = 2 "amplitude of the driving torque";
  parameter Real omega = 2;
  parameter Real tau0 = 1.5 "sliding friction torque";
  parameter Real peak = 1.2 "tau0_max = peak*tau0 breaks the stuck element loose";
  parameter Real w_small = 1e10;
  constant Integer Unknown = 3;
  constant Integer Free = 2;
  constant Integer Forward = 1;
  constant Integer Stuck = 0;
  constant Integer Backward = -1;
  Real phi(start = 0, fixed = true);
  Real w(start = 0, fixed = true);
  Real a;
  Real tau "friction torque";
  Real sa "path parameter";
  Real tau0_max;
  Boolean free;
  Boolean startForward(start = false, fixed = true);
  Boolean startBackward(start = false, fixed = true);
  Boolean locked(start = false);
  Integer mode(start = Unknown, fixed = true);
equation
  der(phi) = w;
  der(w) = a;
  J * a = A * sin(omega * time) - tau;
  tau0_max = peak * tau0;
  free = false;
  startForward = pre(mode) == Stuck and (sa > tau0_max or pre(startForward) and sa > tau0) or
    pre(mode) == Backward and w > w_small or initial() and w > 0;
  startBackward = pre(mode) == Stuck and (sa < -tau0_max or pre(startBackward) and sa < -tau0) or
    pre(mode) == Forward and w < -w_small or initial() and w < 0;
  locked = not free and not (pre(mode) == Forward or startForward or pre(mode) == Backward or startBackward);
  a = if locked then 0 else if free then sa else if startForward then sa - tau0_max
    else if startBackward then sa + tau0_max else if pre(mode) == Forward then sa - tau0_max else sa + tau0_max;
  tau = if locked then sa else if free then 0 else (if startForward then tau0 else if startBackward then -tau0
    else if pre(mode) == Forward then tau0 else -tau0);
  mode = if free then Free else if (pre(mode) == Forward or pre(mode) == Free or startForward) and w > 0 then Forward
    else if (pre(mode) == Backward or pre(mode) == Free or startBackward) and w < 0 then Backward else Stuck;
end FrictionStateMachine;
