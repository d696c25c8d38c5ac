// Steady-state initialisation through an algebraic variable: the model never
// differentiates vR, yet `der(vR) = 0` is a valid initial equation (the MSL's
// machines write der(idq_sr) = zeros(2)). der(vR) = R*der(i) = 0 gives
// i(0) = V/R, where the circuit stays.
model SteadyAlgebraic
  parameter Real V = 10, R = 2, L = 0.5;
  Real i(start = 0);
  Real vR;
  Real p;
equation
  L*der(i) = V - vR;
  vR = R*i;
  p = vR*i + time;
initial equation
  der(vR) = 0;
end SteadyAlgebraic;
