// A parameter computed at initialisation (fixed = false, as the MSL's
// HeatTransfer TwoMasses does): not supported, so its initial equation is
// ignored with a warning, and the states still start from their fixed starts.
model FreeParameter
  parameter Real c = 2;
  parameter Real T_final(fixed = false);
  Real T(start = 3, fixed = true);
initial equation
  T_final = c * T;
equation
  der(T) = -T;
end FreeParameter;
