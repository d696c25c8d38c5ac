// A half-wave rectifier: a sine source charges a capacitor through a
// diode-like element, (vd - Vf)/Ron above its threshold Vf and vd/Roff below.
// The if-expression switches when vd crosses Vf (no when-clause, no reinit),
// and the current jumps there by Vf/Roff: the right-hand side is discontinuous.
model DiodeRC "Sine source, ideal-ish diode, RC load"
  parameter Real A = 2 "Source amplitude (V)";
  parameter Real w = 6 "Source frequency (rad/s)";
  parameter Real Ron = 0.5 "Forward resistance (Ohm)";
  parameter Real Roff = 5 "Backward resistance (Ohm)";
  parameter Real Vf = 0.6 "Threshold voltage (V)";
  parameter Real C = 0.2 "Capacitance (F)";
  parameter Real RL = 5 "Load resistance (Ohm)";
  Real vc(start = 0, fixed = true) "Capacitor voltage (V)";
  Real vd "Diode voltage (V)";
  Real i "Diode current (A)";
equation
  vd = A*sin(w*time) - vc;
  i = if vd > Vf then (vd - Vf)/Ron else vd/Roff;
  C*der(vc) = i - vc/RL;
end DiodeRC;
