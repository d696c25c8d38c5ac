model DiodeThermalLoop
  "A diode whose thermal voltage depends on its own temperature, heated by its
   own loss: one nonlinear block (i, v, vt, Td, dT, Q) in which every unknown
   starts at 0, so that v/vt is 0/0 before tearing"
  constant Real Is = 1e-9 "saturation current";
  parameter Real n = 1.5 "emission coefficient";
  constant Real k = 1.380662e-23 "Boltzmann constant";
  constant Real q = 1.6021892e-19 "electron charge";
  parameter Real R = 5 "series resistance";
  parameter Real G = 0.05 "thermal conductance diode - case";
  parameter Real Gamb = 0.02 "thermal conductance case - ambient";
  parameter Real C = 0.5 "heat capacity of the case";
  parameter Real Tamb = 293.15 "ambient temperature";
  parameter Real V = 2 "source amplitude";
  parameter Real f = 1 "source frequency";
  Real Tc(start = 300) "case temperature";
  output Real Td "diode temperature";
  Real dT "Td - Tc";
  Real vt "thermal voltage";
  Real v "diode voltage";
  output Real i "diode current";
  Real Q "heat the diode dissipates";
  Real u "source voltage";
equation
  u = V*sin(2*3.14159265358979*f*time);
  u = v + R*i;
  i = Is*(exp(v/(n*vt)) - 1);
  vt = k*Td/q;
  Q = v*i;
  Q = G*dT;
  Td = Tc + dT;
  C*der(Tc) = G*dT - Gamb*(Tc - Tamb);
end DiodeThermalLoop;
