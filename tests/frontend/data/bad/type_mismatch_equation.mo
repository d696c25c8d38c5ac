// expect: type mismatch: equation between Real 'x' and Boolean expression 'time > 1'
model type_mismatch_equation
  Real x;
equation
  x = time > 1;
end type_mismatch_equation;
