// expect: reinit() is only allowed inside a when-equation
model reinit_outside_when
  Real x(start = 1);
equation
  der(x) = -x;
  reinit(x, 2);
end reinit_outside_when;
