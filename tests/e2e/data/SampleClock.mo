// sample(start, interval): time events at exactly start + k*interval. A
// counter on sample(0, T) (its tick at t = 0 fires right after
// initialisation), a sample-and-hold on sample(t1, T), sample() inside a
// Boolean expression, and a Boolean b = sample(...) whose edge is counted.
model SampleClock
  parameter Real T = 0.1 "interval";
  parameter Real t1 = 0.05 "first tick of the second clock";
  Real x(start = 0, fixed = true) "x = t";
  Real y(start = 0, fixed = true) "integral of n";
  discrete Integer n(start = 0) "ticks of sample(0, T) so far";
  discrete Real xs(start = -1) "x at the last tick of sample(t1, T)";
  discrete Integer m(start = 0) "ticks of sample(t1, T) with x > 0.52";
  Boolean b "true at the ticks of sample(0, 0.25) only";
  Boolean r "edge(b)";
  discrete Integer e(start = 0) "rising edges of b";
equation
  der(x) = 1;
  der(y) = n;
  when sample(0, T) then
    n = pre(n) + 1;
  end when;
  when sample(t1, T) then
    xs = x;
  end when;
  when x > 0.52 and sample(t1, T) then
    m = pre(m) + 1;
  end when;
  b = sample(0, 0.25);
  r = edge(b);
  when r then
    e = pre(e) + 1;
  end when;
end SampleClock;
