// The mean of |V sin(2 pi f t)| over each half period, written as the MSL's
// Blocks.Math.Mean writes it (sample(t0 + 1/fMean, 1/fMean)): its ticks fall on
// the zero crossings of the sine, where the relation v > 0 raises a state
// event within rounding of the tick. Each mean is 2 V/pi.
// tests/e2e/test_sample_events.cpp.
model RectifiedMean
  constant Real pi = 3.141592653589793;
  parameter Real V = 100;
  parameter Real f = 50;
  parameter Real fMean = 2*f;
  parameter Real t0(fixed = false);
  Real v = V*sin(2*pi*f*time);
  Real u = if v > 0 then v else -v;
  Real x;
  discrete Real y;
  output Real m = y;
initial equation
  t0 = time;
  x = 0;
  y = 0;
equation
  der(x) = u;
  when sample(t0 + 1/fMean, 1/fMean) then
    y = fMean*pre(x);
    reinit(x, 0);
  end when;
end RectifiedMean;
