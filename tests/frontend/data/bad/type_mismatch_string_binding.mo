// expect: type mismatch: binding of Real 'x' is a String ("text")
model type_mismatch_string_binding
  Real x = "text";
end type_mismatch_string_binding;
