// expect: unknown function 'sinn' (did you mean 'sin'?)
model unknown_function
  Real x;
equation
  x = sinn(time);
end unknown_function;
