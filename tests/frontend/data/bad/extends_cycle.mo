// expect: extends cycle: A extends B extends A
model A
  extends B;
  Real a;
end A;

model B
  extends A;
  Real b;
end B;

model extends_cycle
  A inst;
equation
  inst.a = time;
  inst.b = time;
end extends_cycle;
