// Reductions over arrays and matrices, with and without iterators.
model ArrayReductions
  parameter Real w[4] = {4, 1, 3, 2};
  parameter Real W[2, 2] = [1, 2; 3, 4];
  parameter Real total = sum(w);
  parameter Real weighted = sum(i * w[i] for i in 1:4);
  Real x[3](each start = 1, each fixed = true);
  Real s, p, lo, hi, sq, m2;
equation
  der(x) = {-1, -2, -3} .* x;
  s = sum(x);
  p = product(x);
  lo = min(x);
  hi = max(W * x[1:2]);
  sq = sum(x[i]^2 for i in 1:3);
  m2 = max(x[i] + x[j] for i in 1:3, j in 1:2);
end ArrayReductions;
