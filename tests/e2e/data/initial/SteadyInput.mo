// der(y) in an initial equation where y depends on an input: the input's
// derivative is unknown, so lowering refuses it.
model SteadyInput
  input Real u;
  Real x(start = 0);
  Real y;
equation
  der(x) = -x + u;
  y = x + u;
initial equation
  der(y) = 0;
end SteadyInput;
