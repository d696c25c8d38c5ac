// expect: syntax error: missing ';' after the declaration of 'x' (before 'Real')
model missing_semicolon
  Real x(start = 1)
  Real y;
equation
  der(x) = -x;
  y = 2*x;
end missing_semicolon;
