// One initial equation for two states: y keeps its start value (a warning
// names it) and x0 = 1 / y0 makes der(x) = 0.
model UnderDetermined
  Real x(start = 1), y(start = 4);
initial equation
  der(x) = 0;
equation
  der(x) = 1 - x * y;
  der(y) = -y;
end UnderDetermined;
