// expect: modifier 'Rx' does not name an element of class 'Resistor'
model Resistor
  parameter Real R = 1;
  Real v, i;
equation
  v = R*i;
end Resistor;

model bad_modifier
  Resistor R1(Rx = 10);
equation
  R1.v = sin(time);
end bad_modifier;
