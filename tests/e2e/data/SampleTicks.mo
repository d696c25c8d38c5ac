// Sensitivities through sample() ticks whose times move with parameters: tick
// k of sample(start, interval) is at start + k*interval. A counter on
// sample(0, T) integrated by y, a hold of x = t on sample(t1, T) read by z
// (tests/e2e/test_sample_events.cpp). The two clocks never tick together.
model SampleTicks
  parameter Real T = 0.1 "interval";
  parameter Real t1 = 0.05 "first tick of the second clock";
  parameter Real a = 2;
  Real x(start = 0, fixed = true) "x = t";
  Real y(start = 0, fixed = true) "integral of n";
  Real z(start = 1, fixed = true);
  discrete Integer n(start = 0) "ticks of sample(0, T) so far";
  discrete Real xs(start = -1) "x at the last tick of sample(t1, T)";
equation
  der(x) = 1;
  der(y) = n;
  der(z) = -a*z + xs;
  when sample(0, T) then
    n = pre(n) + 1;
  end when;
  when sample(t1, T) then
    xs = x;
  end when;
end SampleTicks;
