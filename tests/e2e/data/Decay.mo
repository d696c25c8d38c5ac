// A first-order plant without declared outputs: measured through its state x,
// its algebraic variable a and its alias b (issue 12.3). x = exp(-k t) x0 + ...
model Decay
  parameter Real k = 2;
  input Real u;
  Real x(start = 1, fixed = true);
  Real a "algebraic";
  Real b "an alias of x";
equation
  der(x) = -k*x + u;
  a = x*x;
  b = x;
end Decay;

model DecayWithOutput "the same plant measured through a declared output"
  extends Decay;
  output Real y;
equation
  y = x;
end DecayWithOutput;
