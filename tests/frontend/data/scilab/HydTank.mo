// Hydraulics: source -> control valve (opening 0.5) -> tank (Bache) -> pipe
// -> sink. The tank level z and mixing enthalpy Hm are states; the tank's
// unused ports Ce2 and Cs1 are left unconnected (the tank sets them itself).
model HydTank
  Source	Src(P0=300000, T0=290, H0=100000, option_temperature=1);
  VanneReglante	Valve(Cvmax=8005.42, p_rho=0);
  Bache	Tank(Patm=100000, A=1, ze1=40, ze2=0, zs1=40, zs2=0, z0=30, T0=290, p_rho=0);
  PerteDP	Pipe(L=10, D=0.2, lambda=0.03, z1=0, z2=0, p_rho=0);
  Puits	Sink(P0=100000, T0=290, H0=100000, option_temperature=1);
equation
  Valve.Ouv = 0.5;
  connect(Src.C, Valve.C1);
  connect(Valve.C2, Tank.Ce1);
  connect(Tank.Cs2, Pipe.C1);
  connect(Pipe.C2, Sink.C);
end HydTank;
