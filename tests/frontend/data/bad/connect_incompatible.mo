// expect: connect of incompatible connectors: Pin (v, flow i) and Flange (s, phi, flow f)
connector Pin
  Real v;
  flow Real i;
end Pin;

connector Flange
  Real s;
  Real phi;
  flow Real f;
end Flange;

model Electric
  Pin p;
equation
  p.v = sin(time);
end Electric;

model Mechanic
  Flange a;
equation
  a.f = 0;
  a.phi = 0;
end Mechanic;

model connect_incompatible
  Electric e;
  Mechanic m;
equation
  connect(e.p, m.a);
end connect_incompatible;
