// A coil whose inductance falls with its current: psi = L i with
// (L - Linf) i = (L0 - Linf) I0 atan(i/I0). At i = 0 the second equation
// holds for every L (0 = 0): the initial system, given i(0) = 0, solves it to
// 0/0 and must keep L's start value; Newton's Jacobian over (i, L) is
// singular there and needs the least-squares step. Driven by cos(t) through
// a resistance R: der(psi) = cos(t) - R i, where i solves
// Linf i + (L0 - Linf) I0 atan(i/I0) = psi (increasing in i).
model SaturatingCoil
  parameter Real L0 = 2 "inductance near i = 0";
  parameter Real Linf = 0.5 "inductance at large currents";
  parameter Real I0 = 0.25 "current scale";
  parameter Real R = 0.5 "resistance";
  Real psi "flux linkage";
  Real i(start = 0, fixed = true);
  Real L(start = L0);
equation
  der(psi) = cos(time) - R*i;
  psi = L*i;
  (L - Linf)*i = (L0 - Linf)*I0*atan(i/I0);
end SaturatingCoil;
