// expect: unbalanced model: 3 unknowns (x, y, z) but 2 equations
model unbalanced_underdetermined
  Real x(start = 1);
  Real y;
  Real z;
equation
  der(x) = -x + z;
  y = 2*x;
end unbalanced_underdetermined;
