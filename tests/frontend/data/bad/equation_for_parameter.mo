// expect: parameter 'k' cannot be determined by an equation (variability)
model equation_for_parameter
  parameter Real k = 2;
  Real x(start = 1);
equation
  der(x) = -k*x;
  k = time;
end equation_for_parameter;
