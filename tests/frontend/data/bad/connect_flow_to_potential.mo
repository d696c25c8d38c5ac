// expect: connect of 'a.c' and 'b.c': 'i' is a flow variable in one connector and a potential in the other
connector PinA
  Real v;
  flow Real i;
end PinA;

connector PinB
  Real v;
  Real i;
end PinB;

model CompA
  PinA c;
equation
  c.v = sin(time);
end CompA;

model CompB
  PinB c;
equation
  c.i = c.v;
end CompB;

model connect_flow_to_potential
  CompA a;
  CompB b;
equation
  connect(a.c, b.c);
end connect_flow_to_potential;
