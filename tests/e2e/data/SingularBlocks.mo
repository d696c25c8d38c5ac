// Linear blocks that become singular while the model runs, with equations
// that stay consistent: part of the solution is then undetermined, and the
// simulator takes the minimum-norm solution (tests/e2e/test_singular_blocks.cpp).
package SingularBlocks
  // A shaft driven by a constant torque against two viscous brakes; at
  // t_hold both clamp it (its acceleration 0 in both equations): how the two
  // share the drive is then undetermined, as for two stuck friction elements
  // on one shaft (the MSL's LossyGearDemo2). The least-norm split of
  // (a, tau1, tau2) is tau1 = tau2 = tau/2.
  model TwoClamps
    parameter Real J = 2 "inertia";
    parameter Real tau = 1 "drive";
    parameter Real d1 = 0.5 "drag of brake 1 before it clamps";
    parameter Real d2 = 0.25 "drag of brake 2 before it clamps";
    parameter Real t_hold = 1 "both brakes clamp";
    Real w(start = 0, fixed = true) "speed";
    Real a "acceleration";
    output Real tau1 "torque of brake 1";
    output Real tau2 "torque of brake 2";
  equation
    der(w) = a;
    J*a = tau - tau1 - tau2;
    0 = if time >= t_hold then a else tau1 - d1*w;
    0 = if time >= t_hold then a else tau2 - d2*w;
  end TwoClamps;

  // The same, but brake 2 clamps to an acceleration that brake 1 forbids:
  // the singular equations contradict each other, and the run stops there.
  model ContradictingClamps
    parameter Real J = 2;
    parameter Real tau = 1;
    parameter Real d1 = 0.5;
    parameter Real d2 = 0.25;
    parameter Real t_hold = 1;
    Real w(start = 0, fixed = true);
    Real a;
    Real tau1;
    Real tau2;
  equation
    der(w) = a;
    J*a = tau - tau1 - tau2;
    0 = if time >= t_hold then a else tau1 - d1*w;
    0 = if w >= 0.3 then a - 1 else tau2 - d2*w;
  end ContradictingClamps;
end SingularBlocks;
