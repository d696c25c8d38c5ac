// expect: lexical error: unterminated /* comment
model unterminated_comment
  Real x(start = 1);
equation
  /* the decay
  der(x) = -x;
end unterminated_comment;
