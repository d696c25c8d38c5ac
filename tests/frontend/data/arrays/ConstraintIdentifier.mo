// Outside optimization classes `constraint` is an ordinary name: of a
// component, in references, and of a for-loop index.
// Solution: constraint = 2 exp(-t), y[i] = i constraint, z = {1, 2}.
model ConstraintIdentifier
  Real constraint(start = 2, fixed = true);
  Real y[2];
  Real z[2];
equation
  der(constraint) = -constraint;
  y = {1, 2} * constraint;
  for constraint in 1:2 loop
    z[constraint] = constraint;
  end for;
end ConstraintIdentifier;
