// expect: unbalanced model: 2 unknowns (x, y) but 3 equations
model unbalanced_overdetermined
  Real x(start = 1);
  Real y;
equation
  der(x) = -x;
  y = 2*x;
  y = x + 1;
end unbalanced_overdetermined;
