// An algebraic loop with sqrt (issue 12; JModelica's EliminationExample is of
// this kind): y + z = x + 2 with z = sqrt(y) is one nonlinear block of two
// unknowns. Newton from y's start, on the wrong side of 0, meets the square
// root of a negative number.
model SqrtLoopPlant
  Real x(start = 2, fixed = true);
  Real y(start = -1, min = 0);
  Real z;
  input Real u(min = -3, max = 3);
equation
  der(x) = u - 0.5*z;
  y + z = x + 2;
  z = sqrt(y);
end SqrtLoopPlant;
