// Starts in equilibrium: the initial equation replaces x = start(x).
model SteadyState
  parameter Real a = 2, b = 3;
  Real x(start = 0);
  Real y;
initial equation
  der(x) = 0;
equation
  der(x) = b - a * x + y;
  y = 0.5 * sin(time);
end SteadyState;
