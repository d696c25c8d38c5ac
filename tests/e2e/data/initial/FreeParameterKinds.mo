// Parameters computed at initialisation of the kinds the MSL's analytic loop
// joints declare: JointRRR's axis n_b is `fixed = false` with Evaluate = true
// (not known at translation, whatever Evaluate says, nor what a parameter
// bound to it evaluates to), and RevoluteWithLengthConstraint's Boolean
// positiveBranch is computed from the positions at t0 (a Boolean or Integer
// parameter computed by `p = expr` is set by the event at initialisation).
//   k = x(0) = 2, k2 = 2 k = 4: z = 4 t (the starts would give 1 and 2);
//   positive = x(0) > 0 = true: x = 2 exp(-t) (false would give 2 exp(t));
//   n = integer(3 x(0)) = 6: y = 6 t.
model FreeParameterKinds
  parameter Real k(fixed = false, start = 1) annotation(Evaluate = true);
  parameter Real k2 = 2 * k annotation(Evaluate = true);
  parameter Boolean positive(fixed = false);
  parameter Integer n(fixed = false, start = 1);
  Real x(start = 2, fixed = true);
  Real z(start = 0, fixed = true);
  Real y(start = 0, fixed = true);
initial equation
  k = x;
  positive = x > 0;
  n = integer(3 * x);
equation
  der(x) = if positive then -x else x;
  der(z) = k2;
  der(y) = n;
end FreeParameterKinds;
