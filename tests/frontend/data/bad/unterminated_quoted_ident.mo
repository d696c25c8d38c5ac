// expect: lexical error: unterminated quoted identifier 'my var
model unterminated_quoted_ident
  Real 'my var(start = 1);
equation
  der('my var') = -'my var';
end unterminated_quoted_ident;
