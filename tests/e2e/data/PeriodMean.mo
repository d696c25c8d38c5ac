// The mean of u = 1 + cos(2*pi*t) over each period 1/f, written as the MSL's
// Blocks.Math.Mean writes it: the period starts at t0, a parameter that the
// initial equations compute (`fixed = false`, `t0 = time`), so the first
// sample() tick is one period after the start, whatever the start time.
// Closed form: tests/e2e/test_sample_events.cpp.
model PeriodMean
  constant Real pi = 3.141592653589793;
  parameter Real f = 2 "Base frequency";
  parameter Real t0(fixed = false) "Start time of simulation";
  Real x "Integrator state";
  Real u = 1 + cos(2*pi*time);
  discrete Real y "Mean of u over the last full period";
  output Real m = y;
initial equation
  t0 = time;
  x = 0;
  y = 0;
equation
  der(x) = u;
  when sample(t0 + 1/f, 1/f) then
    y = f*pre(x);
    reinit(x, 0);
  end when;
end PeriodMean;
