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
  // The friction logic of the MSL's PartialFriction (tau0 = tau0_max =
  // tau_max, never free, w_small unbounded), for a shaft with two of them.
  model StickSlip
    parameter Real tau_max "friction torque, sliding and at rest";
    Real w "speed";
    Real a "acceleration";
    Real tau "friction torque";
    Real sa "path parameter";
    Boolean startForward(start = false, fixed = true);
    Boolean startBackward(start = false, fixed = true);
    Boolean locked(start = false);
    Integer mode(start = 3, fixed = true) "-1 backward, 0 stuck, 1 forward, 3 unknown";
  equation
    startForward = pre(mode) == 0 and (sa > tau_max or pre(startForward) and sa > tau_max)
                   or initial() and w > 0;
    startBackward = pre(mode) == 0 and (sa < -tau_max or pre(startBackward) and sa < -tau_max)
                    or initial() and w < 0;
    locked = not (pre(mode) == 1 or startForward or pre(mode) == -1 or startBackward);
    a = if locked then 0 else if startForward then sa - tau_max else if startBackward then sa + tau_max
        else if pre(mode) == 1 then sa - tau_max else sa + tau_max;
    tau = if locked then sa else if startForward then tau_max else if startBackward then -tau_max
          else if pre(mode) == 1 then tau_max else -tau_max;
    mode = if (pre(mode) == 1 or startForward) and w > 0 then 1
           else if (pre(mode) == -1 or startBackward) and w < 0 then -1 else 0;
  end StickSlip;

  // A spinning shaft driven forward against a weak bearing and a strong
  // brake stops at w0 J/(bearing + brake - drive) with both stuck. Their
  // least-norm split (drive/2 each) asks more than the bearing holds, so it
  // starts forward; sliding at its limit while the brake keeps the shaft at
  // rest, its sa is exactly tau_max, and `sa > tau_max` is false again: a
  // cycle of the event iteration, which the relation's hysteresis ends with
  // the bearing at its limit and the brake holding the rest.
  model BearingAndBrake
    parameter Real J = 1;
    parameter Real drive = 2;
    parameter Real w0 = 1;
    StickSlip bearing(tau_max = 0.5);
    StickSlip brake(tau_max = 10);
    Real w(start = w0, fixed = true);
    Real a;
  equation
    der(w) = a;
    J*a = drive - bearing.tau - brake.tau;
    bearing.w = w;
    bearing.a = a;
    brake.w = w;
    brake.a = a;
  end BearingAndBrake;
end SingularBlocks;
