// No states: a voltage divider driven by a sine, with a switch that closes
// at t = 0.5 (an event) and a nonlinear element solved at every output time.
model Resistive
  parameter Real R1 = 2, R2 = 3, V = 10;
  Real v;
  output Real i, w;
equation
  v = V * sin(time);
  i = v / (if time > 0.5 then R1 else R1 + R2);
  w ^ 3 + w = i;
end Resistive;
