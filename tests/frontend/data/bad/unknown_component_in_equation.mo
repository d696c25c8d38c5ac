// expect: unknown component 'z' in an equation (did you mean 'x'?)
model unknown_component_in_equation
  Real x(start = 1);
  Real y;
equation
  der(x) = -x;
  y = 2*z;
end unknown_component_in_equation;
