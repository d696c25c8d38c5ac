// expect: lexical error: unterminated string literal (the description of 'x')
model unterminated_string
  Real x(start = 1) "position;
equation
  der(x) = -x;
end unterminated_string;
