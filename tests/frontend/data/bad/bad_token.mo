// expect: lexical error: unexpected character '$'
model bad_token
  Real x(start = 1);
equation
  der(x) = -x $ 2;
end bad_token;
