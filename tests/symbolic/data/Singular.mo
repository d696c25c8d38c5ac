// Balanced in count but structurally singular: x is determined twice and y
// by nothing.
model Singular
  Real x;
  Real y;
equation
  x = sin(time);
  x = cos(time);
end Singular;
