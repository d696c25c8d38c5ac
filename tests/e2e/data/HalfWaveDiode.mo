// A half-wave rectifier: a sine source V*sin(2*pi*f*t) drives a resistor R
// through an ideal diode written as the MSL's IdealDiode writes it (the
// Boolean `off = s < 0` and the knee, on-resistance and leakage laws in the
// auxiliary variable s), so that s, the diode's voltage and the current are
// one algebraic loop. The diode is a Boolean equation with a relation and no
// pre(): a discrete variable, held between events, switching where the
// source crosses Vknee*(1 + R*Goff). q counts the charge through the load.
// Closed form: tests/e2e/test_circuits.cpp.
model HalfWaveDiode
  constant Real pi = 3.141592653589793;
  parameter Real V = 10;
  parameter Real f = 50;
  parameter Real R = 10;
  parameter Real Ron = 1e-2;
  parameter Real Goff = 1e-5;
  parameter Real Vknee = 0.7;
  output Real vd "diode voltage";
  Real i "current";
  Real s(start = 0) "auxiliary variable of the diode's characteristic";
  Boolean off(start = true) "the diode blocks";
  Real q(start = 0, fixed = true) "charge through the load";
equation
  off = s < 0;
  vd = s*(if off then 1 else Ron) + Vknee;
  i = s*(if off then Goff else 1) + Goff*Vknee;
  V*sin(2*pi*f*time) = vd + R*i;
  der(q) = i;
end HalfWaveDiode;
