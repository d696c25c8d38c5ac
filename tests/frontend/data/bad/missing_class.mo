// expect: (run with --class DoesNotExist) class 'DoesNotExist' not found; the file defines 'missing_class'
model missing_class
  Real x(start = 1);
equation
  der(x) = -x;
end missing_class;
