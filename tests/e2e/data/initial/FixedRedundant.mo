// x is a state fixed at 1; y (y + 0.1 sin y = 2 x, solved for y) is also declared fixed (start 5), which
// the system cannot admit beside x's: y's flag gives way with a warning (as
// a Coselica body's velocity fixed beside its joint's).
model FixedRedundant
  Real x(start = 1, fixed = true);
  Real y(start = 5, fixed = true);
equation
  der(x) = -x;
  y + 0.1 * sin(y) = 2 * x;
end FixedRedundant;
