// Parameters computed at initialisation (fixed = false, as the MSL's
// HeatTransfer TwoMasses and SaturatingInductor declare them): each is an
// unknown of the initial system and keeps its value afterwards.
//   T_final = c T(0) = 6;
//   der(x)(0) = -x(0)/tau = -r, so tau = x(0)/r = 2 and x = 2 exp(-r t/2).
model FreeParameter
  parameter Real c = 2;
  parameter Real r = 1;
  parameter Real T_final(fixed = false);
  parameter Real tau(fixed = false, start = 1) "Newton's guess";
  Real T(start = 3, fixed = true);
  Real x(start = 2, fixed = true);
initial equation
  T_final = c * T;
  der(x) = -r;
equation
  der(T) = -T;
  der(x) = -x/tau;
end FreeParameter;
