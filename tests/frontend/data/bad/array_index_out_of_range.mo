// expect: index 3 out of range for 'x' (size 2)
model array_index_out_of_range
  Real x[2];
equation
  x[1] = time;
  x[2] = 2*time;
  x[3] = 0;
end array_index_out_of_range;
