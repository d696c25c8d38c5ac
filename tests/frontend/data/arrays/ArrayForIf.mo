// Array equations inside for- and if-equations: a branch chosen by a
// parameter, a time-dependent branch on whole arrays, and a nested loop
// over a matrix. Solution: x[i] = exp(-i t); y = x before t = 1, 3 x after.
model ArrayForIf
  parameter Integer n = 3;
  parameter Boolean doubled = true;
  Real x[n](each start = 1, each fixed = true);
  Real y[n];
  Real w[n];
  Real M[2, n];
equation
  for i in 1:n loop
    der(x[i]) = -i * x[i];
  end for;
  if doubled then
    w = 2 * x;
  else
    w = x;
  end if;
  if time < 1 then
    y = x;
  else
    y = 3 * x;
  end if;
  for i in 1:2, j in 1:n loop
    M[i, j] = i * x[j];
  end for;
end ArrayForIf;
