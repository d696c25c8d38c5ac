model DiodeLimitLoop
  "A diode heated by its own loss (as tearing/DiodeThermalLoop.mo) whose
   exponential is limited as in the MSL's diodes: linear above
   v/(n*vt) = Maxexp. The relation reads v and vt, unknowns of the torn
   nonlinear block (i, v, vt, Td, dT, Q): the event is located, and the
   right-hand sides before and after it computed, through Newton. The state is
   the case's rise above ambient (small, so that central differences of it
   resolve the effects of the event times)."
  constant Real Is = 1e-9 "saturation current";
  parameter Real n = 1.5 "emission coefficient";
  constant Real k = 1.380662e-23 "Boltzmann constant";
  constant Real q = 1.6021892e-19 "electron charge";
  parameter Real Maxexp = 15 "above it the current grows linearly";
  parameter Real R = 5 "series resistance";
  parameter Real G = 0.05 "thermal conductance diode - case";
  parameter Real Gamb = 0.02 "thermal conductance case - ambient";
  parameter Real C = 0.5 "heat capacity of the case";
  parameter Real Tamb = 293.15 "ambient temperature";
  parameter Real V = 2 "source amplitude";
  parameter Real f = 1 "source frequency";
  Real theta(start = 6.85) "case temperature above ambient";
  Real Tc "case temperature";
  Real Td "diode temperature";
  Real dT "Td - Tc";
  Real vt "thermal voltage";
  Real v "diode voltage";
  Real i "diode current";
  Real Q "heat the diode dissipates";
  Real u "source voltage";
equation
  u = V*sin(2*3.14159265358979*f*time);
  u = v + R*i;
  i = Is*(if v/(n*vt) > Maxexp then exp(Maxexp)*(1 + v/(n*vt) - Maxexp) - 1 else exp(v/(n*vt)) - 1);
  vt = k*Td/q;
  Q = v*i;
  Q = G*dT;
  Td = Tc + dT;
  Tc = Tamb + theta;
  C*der(theta) = Q - Gamb*theta;
end DiodeLimitLoop;
