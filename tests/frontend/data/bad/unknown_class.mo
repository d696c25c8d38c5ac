// expect: unknown class 'Resistr' in the declaration of 'R1'
model Resistor
  parameter Real R = 1;
  Real v, i;
equation
  v = R*i;
end Resistor;

model unknown_class
  Resistr R1(R = 10);
equation
  R1.v = sin(time);
end unknown_class;
