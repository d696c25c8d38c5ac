// expect: duplicate declaration of 'x' (first declared on line 3)
model duplicate_declaration
  Real x(start = 1);
  Real y;
  Real x;
equation
  der(x) = -x;
  y = x;
end duplicate_declaration;
