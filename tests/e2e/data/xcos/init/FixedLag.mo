model FixedLag
  Real x; Real y;
equation
  der(x) = -x;
  y = 2*x;
end FixedLag;
