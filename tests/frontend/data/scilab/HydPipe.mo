// Hydraulics: a pressure source feeding a sink through one pipe (PerteDP,
// quadratic Darcy-Weisbach loss). The PortPHQ connectors have no flow
// variables, so every connect() is four plain equalities (P, H, Q, Hm).
// Purely algebraic (no der): the flow Q solves deltaP = 8*khi*Q*|Q|/(pi^2*D^4*rho).
model HydPipe
  parameter Real P0_11(fixed=false) = 300000 "P0_11";
  parameter Real P0_31(fixed=false) = 100000 "P0_31";
  Source	Src(P0=P0_11, T0=290, H0=100000, option_temperature=1);
  PerteDP	Pipe(L=10, D=0.2, lambda=0.03, z1=0, z2=0, p_rho=0);
  Puits	Sink(P0=P0_31, T0=290, H0=100000, option_temperature=1);
equation
  connect(Src.C, Pipe.C1);
  connect(Pipe.C2, Sink.C);
end HydPipe;
