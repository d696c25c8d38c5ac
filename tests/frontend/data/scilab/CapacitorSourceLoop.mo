// A sine voltage source directly across two capacitors in series (a loop of
// a voltage source and capacitors): C1.v + C2.v = Vs.v fixes one capacitor
// voltage algebraically; a resistor across C2 makes the split dynamic.
// Structurally singular as written (index 2); one state after reduction.
model CapacitorSourceLoop
  SineVoltage	Vs(V=1, freqHz=5);
  Capacitor	C1(C=1e-3, v(start=0));
  Capacitor	C2(C=1e-3, v(start=0));
  Resistor	R2(R=100);
  Ground	G1;
equation
  connect(Vs.p, C1.p);
  connect(C1.n, C2.p);
  connect(C1.n, R2.p);
  connect(C2.n, G1.p);
  connect(R2.n, G1.p);
  connect(Vs.n, G1.p);
end CapacitorSourceLoop;
