// A relation whose switch drives its own indicator back: x falls to 0 at
// t = 1, then der(x) = +1 below 0 and -1 above, a sliding mode (Filippov's
// solution stays at x = 0) that events cannot follow: a root every 0.4 ns,
// none of them changing a discrete variable. The run must end
// with a diagnostic naming x, keeping x = 1 - t before; it used to run for ever.
model SlidingSwitch
  Real x(start = 1, fixed = true);
equation
  der(x) = if x > 0 then -1 else 1;
end SlidingSwitch;
