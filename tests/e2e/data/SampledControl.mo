// A plant under a sampled controller: a sample-and-hold of the state on
// initial() and on sample() (the MSL's ZeroOrderHold pattern), the held value
// computed from another value of the same clause, and a force latched from
// the states and time at a state event. Their sensitivities are carried as
// discrete sensitivities (docs/events.md): tests/e2e/test_event_sensitivities.cpp.
model SampledControl
  parameter Real a = 1.5 "plant pole";
  parameter Real k = 2 "feedback gain";
  parameter Real T = 0.1 "sampling period";
  parameter Real r = 1 "set point";
  parameter Real xs = 0.5 "latch level";
  parameter Real c = 0.3;
  parameter Real x0 = 0.1;
  Real x(start = x0, fixed = true);
  Real v(start = 0, fixed = true);
  discrete Real e(start = 0) "control error";
  discrete Real u(start = 0) "held control";
  discrete Real F(start = 0) "force latched at the crossing";
equation
  der(x) = -a*x + u;
  der(v) = F - c*v + x;
  when {initial(), sample(0.2, T)} then
    e = r - x;
    u = k*e;
  end when;
  when x > xs then
    F = c*x + pre(F) + v + 0.1*time;
  end when;
end SampledControl;
