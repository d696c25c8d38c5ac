// expect: syntax error: unbalanced parenthesis, ')' missing before ';'
model unbalanced_paren
  Real x(start = 1);
equation
  der(x) = -(x + 2*(x - 1);
end unbalanced_paren;
