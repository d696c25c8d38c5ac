// expect: lexical error: malformed number '1.5e' (exponent without digits)
model malformed_number
  Real x(start = 1);
equation
  der(x) = -1.5e*x;
end malformed_number;
