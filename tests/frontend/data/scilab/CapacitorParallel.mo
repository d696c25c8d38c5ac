// Two capacitors directly in parallel, charged through a resistor: the two
// capacitor voltages are tied by C1.v = C2.v (a capacitor loop), so the model
// is structurally singular as written and needs index reduction; one state.
model CapacitorParallel
  ConstantVoltage	V1(V=5);
  Resistor	R1(R=100);
  Capacitor	C1(C=1e-3, v(start=0));
  Capacitor	C2(C=2e-3, v(start=0));
  Ground	G1;
equation
  connect(V1.p, R1.p);
  connect(R1.n, C1.p);
  connect(R1.n, C2.p);
  connect(C1.n, G1.p);
  connect(C2.n, G1.p);
  connect(V1.n, G1.p);
end CapacitorParallel;
