// Series RLC circuit switched onto a constant voltage at t = 0 (a step),
// built from Scilab's Electrical.mo.
// Analytic solution (C1.v(0) = 0, L1.i(0) = 0), V = 1, R = 10, L = 0.1, C = 1e-3:
//   w0 = 1/sqrt(L*C) = 100 rad/s, zeta = R/2*sqrt(C/L) = 0.5 (underdamped),
//   alpha = R/(2*L) = 50 1/s, wd = w0*sqrt(1 - zeta^2) = 86.60254037844386 rad/s
//   C1.v(t) = V*(1 - exp(-alpha*t)*(cos(wd*t) + alpha/wd*sin(wd*t)))
//   L1.i(t) = V/(L*wd)*exp(-alpha*t)*sin(wd*t)
model RLCSeries
  parameter Real R0 = 10 "Resistance";
  parameter Real L0 = 0.1 "Inductance";
  parameter Real C0 = 0.001 "Capacitance";
  ConstantVoltage V1(V=1);
  Resistor R1(R=R0);
  Inductor L1(L=L0, i(start=0));
  Capacitor C1(C=C0, v(start=0));
  Ground G1;
equation
  connect(V1.p, R1.p);
  connect(R1.n, L1.p);
  connect(L1.n, C1.p);
  connect(C1.n, V1.n);
  connect(V1.n, G1.p);
end RLCSeries;
