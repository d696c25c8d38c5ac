// der() in an initial equation of a variable computed through a nonlinear
// block (y + y^3 = i) and a function of it: d/dt of both steps join the
// initial system. der(z) = (1 + cos y)·der(y) = 0 holds where der(i) = 0:
// i(0) = V/R.
model SteadyImplicit
  parameter Real V = 10, R = 2, L = 0.5;
  Real i(start = 1);
  Real y(start = 1);
  Real z;
equation
  L*der(i) = V - R*i;
  y + y^3 = i;
  z = sin(y) + y;
initial equation
  der(z) = 0;
end SteadyImplicit;
