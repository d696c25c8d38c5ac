// Inverting amplifier with Scilab's ideal OpAmp (nullor: in_p.v = in_n.v,
// no input currents, output voltage free): gain -Rf/Rin = -10.
// Purely algebraic: no states.
model OpAmpInverting
  SineVoltage	Vin(V=1, freqHz=10);
  Resistor	Rin(R=1000);
  Resistor	Rf(R=10000);
  Resistor	Rload(R=2000);
  OpAmp	OA;
  Ground	G1;
equation
  connect(Vin.p, Rin.p);
  connect(Rin.n, OA.in_n);
  connect(Rf.p, OA.in_n);
  connect(Rf.n, OA.out);
  connect(OA.out, Rload.p);
  connect(OA.in_p, G1.p);
  connect(Rload.n, G1.p);
  connect(Vin.n, G1.p);
end OpAmpInverting;
