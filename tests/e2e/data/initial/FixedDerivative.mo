// fixed = true on a variable that becomes a state's derivative (the MSL's
// Inertia declares `a = der(w)` and examples write `a(fixed = true, start = 0)`):
// a = 0 at t0 is an initial equation, so w(0) = 2 and w stays there. Without
// it w would start at its start value 0 and rise as 2 (1 - exp(-t)).
model FixedDerivative
  Real w;
  Real a(start = 0, fixed = true);
equation
  a = der(w);
  a = 2 - w;
end FixedDerivative;
