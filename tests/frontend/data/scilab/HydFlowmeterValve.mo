// Hydraulics: source -> flowmeter -> valve with a sinusoidal opening -> pipe
// -> sink; algebraic, with if-expressions on the flow direction.
model HydFlowmeterValve
  Source	Src(P0=300000, T0=290, H0=100000, option_temperature=1);
  Flowmeter	Fm(Qini=1);
  VanneReglante	Valve(Cvmax=8005.42, p_rho=0);
  PerteDP	Pipe(L=50, D=0.1, lambda=0.02, z1=0, z2=5, p_rho=0);
  Puits	Sink(P0=100000, T0=290, H0=100000, option_temperature=1);
equation
  Valve.Ouv = 0.6 + 0.3*sin(2*3.141592653589793*0.1*time);
  connect(Src.C, Fm.C1);
  connect(Fm.C2, Valve.C1);
  connect(Valve.C2, Pipe.C1);
  connect(Pipe.C2, Sink.C);
end HydFlowmeterValve;
