// A first-order plant under a sampled proportional controller: at each tick
// of sample(0, T) the controller holds uh = kp·(r − x) until the next one.
// uh is a held value (set from the continuous part), so studies on this
// model have one unknown uh per phase (docs/events.md). Used by
// SampledEstimate.mop, SampledPeriod*.mop and SampledMonteCarlo.mop;
// SampledTrack.mop and SampledDesign.mop have the set point as an input.
model SampledLoop
  parameter Real a(min = 0.1, max = 10) = 1.5 "plant pole";
  parameter Real b(min = 0.1, max = 10) = 2 "plant gain";
  parameter Real kp = 0.8 "controller gain";
  parameter Real T = 0.2 "sample period";
  parameter Real r = 1 "set point";
  Real x(start = 0, fixed = true);
  discrete Real uh(start = 0) "the held control";
equation
  der(x) = -a*x + b*uh;
  when sample(0, T) then
    uh = kp*(r - x);
  end when;
end SampledLoop;
