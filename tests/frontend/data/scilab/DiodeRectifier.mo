// Half-wave rectifier: 50 Hz sine source, Scilab's exponential Diode
// (noEvent if-expression), load resistor with a smoothing capacitor.
model DiodeRectifier
  SineVoltage	Vs(V=10, freqHz=50);
  Diode	D1;
  Resistor	Rload(R=100);
  Capacitor	Cs(C=1e-4, v(start=0));
  Ground	G1;
equation
  connect(Vs.p, D1.p);
  connect(D1.n, Rload.p);
  connect(D1.n, Cs.p);
  connect(Rload.n, G1.p);
  connect(Cs.n, G1.p);
  connect(Vs.n, G1.p);
end DiodeRectifier;
