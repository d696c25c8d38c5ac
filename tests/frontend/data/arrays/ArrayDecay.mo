// Array equations: der() and arithmetic over whole arrays, an array start
// value and an array binding. Solution: x[i] = x0[i] exp(-k t), y = 2 x.
model ArrayDecay
  parameter Real k = 0.5;
  parameter Real x0[3] = {1, 2, 3};
  Real x[3](start = x0, each fixed = true);
  Real y[3];
  Real z[3] = -y;
equation
  der(x) = -k * x;
  y = 2 * x;
end ArrayDecay;
