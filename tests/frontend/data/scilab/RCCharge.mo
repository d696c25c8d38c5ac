// RC charging circuit from Scilab's Electrical.mo, written the way Xcos
// writes a diagram: parameters declared (fixed=false) at top level, one
// component per block (tab between type and name), connect equations.
// Analytic solution (all states 0 at t = 0):
//   tau = R*C = 1000*1e-3 = 1 s
//   C1.v(t) = V*(1 - exp(-t/tau)) = 10*(1 - exp(-t))
//   R1.i(t) = V/R*exp(-t/tau) = 0.01*exp(-t)
model RCCharge
  parameter Real V_11(fixed=false) = 10 "V_11";
  parameter Real R_21(fixed=false) = 1000 "R_21";
  parameter Real C_31(fixed=false) = 0.001 "C_31";
  ConstantVoltage	V1(V=V_11);
  Resistor	R1(R=R_21);
  Capacitor	C1(C=C_31, v(start=0));
  Ground	G1;
equation
  connect(V1.p, R1.p);
  connect(R1.n, C1.p);
  connect(C1.n, V1.n);
  connect(V1.n, G1.p);
end RCCharge;
