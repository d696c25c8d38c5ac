// A variable that is not a state declared fixed = true, with no initial
// equation: y = 2 x holds at t0 with y = 4, so x(0) = 2 (its start 0 is
// only a guess). Xcos diagrams bring such flags through their init file.
model FixedAlgebraic
  Real x(start = 0);
  Real y(start = 4, fixed = true);
equation
  der(x) = -x;
  y = 2 * x;
end FixedAlgebraic;
