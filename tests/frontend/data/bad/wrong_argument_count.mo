// expect: wrong number of arguments: sin expects 1, got 2
model wrong_argument_count
  Real x;
equation
  x = sin(time, 2);
end wrong_argument_count;
