// expect: type mismatch: Boolean parameter 'b' bound to a Real expression (1.5)
model type_mismatch_boolean_from_real
  parameter Boolean b = 1.5;
  Real x;
equation
  x = if b then 1 else 0;
end type_mismatch_boolean_from_real;
