// A half-wave rectifier: a sine source charges a capacitor through a
// diode-like element, conductance 1/Ron forwards and 1/Roff backwards. The
// if-expression switches when the diode voltage crosses zero (no when-clause,
// no reinit: the right-hand side jumps).
model DiodeRC "Sine source, ideal-ish diode, RC load"
  parameter Real A = 2 "Source amplitude (V)";
  parameter Real w = 6 "Source frequency (rad/s)";
  parameter Real Ron = 0.5 "Forward resistance (Ohm)";
  parameter Real Roff = 50 "Backward resistance (Ohm)";
  parameter Real C = 0.2 "Capacitance (F)";
  parameter Real RL = 5 "Load resistance (Ohm)";
  Real vc(start = 0, fixed = true) "Capacitor voltage (V)";
  Real vd "Diode voltage (V)";
  Real i "Diode current (A)";
equation
  vd = A*sin(w*time) - vc;
  i = if vd > 0 then vd/Ron else vd/Roff;
  C*der(vc) = i - vc/RL;
end DiodeRC;
