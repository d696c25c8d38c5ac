// x0 solves a nonlinear initial equation with a parameter: x0^3 + x0 = k
// (x0 = 2 at k = 10, from the guess 0); v is fixed at its start.
model NonlinearStart
  parameter Real k = 10, c = 0.5;
  Real x(start = 0, fixed = false);
  Real v(start = 0.1, fixed = true);
initial equation
  x^3 + x = k;
equation
  der(x) = v;
  der(v) = -c * x - 0.1 * v;
end NonlinearStart;
