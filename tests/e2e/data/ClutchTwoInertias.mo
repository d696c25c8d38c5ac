// Two inertias coupled by a Coulomb clutch written with the equations of the
// MSL's Rotational.Interfaces.PartialFriction and Components.Clutch (3.2.2):
// the mode machine (startForward, startBackward, locked, mode) reads pre()
// outside when-clauses, and the friction torque and the relative acceleration
// form a mixed system with it. Inertia 1 is driven by A*sin(omega*time) and
// starts faster than inertia 2: the clutch slides backward, locks, breaks
// loose, ... (tests/e2e/test_friction_modes.cpp has the exact piecewise
// solution). When it locks after sliding, the event iteration must find
// `locked` before `sa`: with J2 small, an `sa` computed under the sliding
// hypothesis makes `startForward` true and the clutch chatters.
model ClutchTwoInertias
  parameter Real J1 = 1;
  parameter Real J2 = 0.05;
  parameter Real A = 40 "amplitude of the driving torque";
  parameter Real omega = 2;
  parameter Real tau0 = 1 "sliding friction torque";
  parameter Real peak = 1.2 "tau0_max = peak*tau0 breaks the locked clutch loose";
  parameter Real w_small = 1e10;
  constant Integer Unknown = 3;
  constant Integer Free = 2;
  constant Integer Forward = 1;
  constant Integer Stuck = 0;
  constant Integer Backward = -1;
  Real phi1(start = 0, fixed = true);
  Real w1(start = 2, fixed = true);
  Real phi2(start = 0, fixed = true);
  Real w2(start = 0, fixed = true);
  Real a1;
  Real a2;
  Real w_rel "w2 - w1";
  Real a_rel;
  Real tau "clutch torque on inertia 1 (minus that on inertia 2)";
  Real sa "path parameter";
  Real tau0_max;
  Boolean free;
  Boolean startForward(start = false, fixed = true);
  Boolean startBackward(start = false, fixed = true);
  Boolean locked(start = false);
  Integer mode(start = Unknown, fixed = true);
equation
  der(phi1) = w1;
  der(w1) = a1;
  der(phi2) = w2;
  der(w2) = a2;
  J1 * a1 = A * sin(omega * time) + tau;
  J2 * a2 = -tau;
  w_rel = w2 - w1;
  a_rel = a2 - a1;
  tau0_max = peak * tau0;
  free = false;
  startForward = pre(mode) == Stuck and (sa > tau0_max or pre(startForward) and sa > tau0) or
    pre(mode) == Backward and w_rel > w_small or initial() and w_rel > 0;
  startBackward = pre(mode) == Stuck and (sa < -tau0_max or pre(startBackward) and sa < -tau0) or
    pre(mode) == Forward and w_rel < -w_small or initial() and w_rel < 0;
  locked = not free and not (pre(mode) == Forward or startForward or pre(mode) == Backward or startBackward);
  a_rel = if locked then 0 else if free then sa else if startForward then sa - tau0_max
    else if startBackward then sa + tau0_max else if pre(mode) == Forward then sa - tau0_max else sa + tau0_max;
  tau = if locked then sa else if free then 0 else (if startForward then tau0 else if startBackward then -tau0
    else if pre(mode) == Forward then tau0 else -tau0);
  mode = if free then Free else if (pre(mode) == Forward or pre(mode) == Free or startForward) and w_rel > 0 then Forward
    else if (pre(mode) == Backward or pre(mode) == Free or startBackward) and w_rel < 0 then Backward else Stuck;
end ClutchTwoInertias;
