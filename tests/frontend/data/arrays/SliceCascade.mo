// Slices: ranges with and without a step, `end`, `:` on a matrix. s holds
// the running sums of x, e the elements of x at odd positions, c a column
// and r a row of a parameter matrix. Solution: x[i] = exp(-i t).
model SliceCascade
  parameter Real A[2, 3] = [1, 2, 3; 4, 5, 6];
  Real x[5](each start = 1, each fixed = true);
  Real s[5];
  Real e[3];
  Real c[2];
  Real r[3];
  Real last;
equation
  for i in 1:5 loop
    der(x[i]) = -i * x[i];
  end for;
  s[1] = x[1];
  s[2:end] = s[1:end - 1] + x[2:5];
  e = x[1:2:end];
  c = A[:, 2] .* x[{1, 2}];
  r = A[end, :] * x[end];
  last = x[end] + s[end - 1];
end SliceCascade;
