// A nonlinear loop with two solutions, and no way to start at 0: the torn
// residual's derivative vanishes there whichever variable is torn. The
// author's start value on y is the guess that picks the solution (y < 0), as
// the MSL's Schmitt trigger gives its resistor current one: y must be the
// tearing variable, so that Newton starts from it.
model StartGuessRoot
  output Real x;
  output Real y(start = -3);
  Real s(start = 0, fixed = true);
equation
  y = 2*x + sin(time);
  x*y = 8 + time;
  der(s) = x;
end StartGuessRoot;
