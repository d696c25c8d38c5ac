// expect: syntax error: unexpected end of file, 'end missing_end;' missing
model missing_end
  Real x(start = 1);
equation
  der(x) = -x;
