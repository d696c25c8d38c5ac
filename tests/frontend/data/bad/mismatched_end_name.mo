// expect: 'end Circuit;' does not match 'model mismatched_end_name'
model mismatched_end_name
  Real x(start = 1);
equation
  der(x) = -x;
end Circuit;
