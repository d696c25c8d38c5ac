// Two inductors in series: the node between them joins only L1 and L2, a
// cut-set of inductors, so L1.i = L2.i ties the inductor currents and the
// model is structurally singular as written; one state after reduction.
model InductorCutset
  SineVoltage	Vs(V=10, freqHz=50);
  Resistor	R1(R=10);
  Inductor	L1(L=0.01, i(start=0));
  Inductor	L2(L=0.02, i(start=0));
  Ground	G1;
equation
  connect(Vs.p, R1.p);
  connect(R1.n, L1.p);
  connect(L1.n, L2.p);
  connect(L2.n, Vs.n);
  connect(Vs.n, G1.p);
end InductorCutset;
