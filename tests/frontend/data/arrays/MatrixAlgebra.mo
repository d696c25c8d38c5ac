// Matrix expressions: products, transpose, identity, constructors with array
// elements, cat, element-wise operators, outerProduct, diagonal, linspace,
// scalar, vector, matrix, ndims, skew, symmetric and iterator constructors.
model MatrixAlgebra
  parameter Real A[2, 2] = [-1, 1; 0, -2];
  parameter Real d[2] = {2, 3};
  parameter Real G[2, 3] = {i * 10 + j for j in 1:3, i in 1:2};
  Real x[2](start = {1, 1}, each fixed = true);
  Real Ax[2], xA[2], At[2, 2], B[2, 4], C[3, 2], E[4, 2];
  Real el[2], dv[2], pw[2], ad[2], sb[2];
  Real op[2, 2], dg[2, 2], ls[3], sc, v[4], mt[2, 1], nd;
  Real sk[3, 3], sy[2, 2], q;
equation
  der(x) = A * x;
  Ax = A * x;
  xA = x * A;
  At = transpose(A) + identity(2);
  B = [A, diagonal(x)];
  C = [transpose(A); {x}];
  E = cat(1, A, [x, d]);
  el = x .* d;
  dv = x ./ d;
  pw = x .^ 2;
  ad = x .+ 1;
  sb = 1 .- x;
  op = outerProduct(x, d);
  dg = diagonal(d) * 2;
  ls = linspace(0, 1, 3) * x[1];
  sc = scalar({{x[1]}});
  v = vector([x; d]);
  mt = matrix(x);
  nd = ndims(G) + G[2, 3];
  sk = skew({x[1], x[2], 1});
  sy = symmetric([x[1], x[2]; 0, x[1]]);
  q = x * A * x;
end MatrixAlgebra;
