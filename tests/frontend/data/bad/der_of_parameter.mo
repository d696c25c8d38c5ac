// expect: der() applied to parameter 'k' (a parameter has no time derivative to solve for)
model der_of_parameter
  parameter Real k = 2;
  Real x(start = 1);
equation
  der(x) = -k*x;
  der(k) = x;
end der_of_parameter;
