// Ideal transformer (v1 = N*v2, i2 = -N*i1), N = 2, fed by a 230 V 50 Hz
// source through a series resistance, secondary loaded by R and L in series.
// Primary and secondary sides are separate circuits, each with its own ground.
model TransformerLoad
  parameter Real N_11(fixed=false) = 2 "N_11";
  VsourceAC	Vp(VA=230, f=50);
  Resistor	Rp(R=0.5);
  IdealTransformer	T1(N=N_11);
  Resistor	Rl(R=20);
  Inductor	Ll(L=0.05, i(start=0));
  Ground	Gp;
  Ground	Gs;
equation
  connect(Vp.p, Rp.p);
  connect(Rp.n, T1.p1);
  connect(T1.n1, Vp.n);
  connect(Vp.n, Gp.p);
  connect(T1.p2, Rl.p);
  connect(Rl.n, Ll.p);
  connect(Ll.n, T1.n2);
  connect(T1.n2, Gs.p);
end TransformerLoad;
