// x is a state tied to an input: index reduction would have to differentiate u.
model InputDerivative
  input Real u;
  Real x(start = 0);
  Real v;
equation
  x = u;
  der(x) = v;
end InputDerivative;
