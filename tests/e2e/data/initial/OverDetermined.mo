// x is fixed at its start and also set by an initial equation.
model OverDetermined
  Real x(start = 1, fixed = true);
initial equation
  x = 2;
equation
  der(x) = -x;
end OverDetermined;
