// Starts in equilibrium under the input's value at the start time t0:
// x0 = (b + u(t0)) / a, and w0 solves w^3 + w = u(t0) (Newton), for any t0.
model InputSteadyState
  input Real u;
  parameter Real a = 2, b = 1;
  Real x(start = 0);
  Real w(start = 1);
initial equation
  der(x) = 0;
  der(w) = 0;
equation
  der(x) = b + u - a * x;
  der(w) = u - w^3 - w;
end InputSteadyState;
