// A parameter declared with annotation(Evaluate = true) is a structural
// value, as the MSL's HeatingNPN_OrGate uses CapVal = 0 to switch off every
// capacitance: C*der(v) with C = 0 must drop der(v), so that v is algebraic
// (v = R*i) instead of a state of a singular system. Exact: v = R*sin(time).
model EvaluatedCapacitance
  parameter Real CapVal = 0 annotation(Evaluate = true);
  parameter Real C = CapVal;
  parameter Real R = 2;
  output Real v(start = 0);
  Real i;
equation
  i = C*der(v) + v/R;
  i = sin(time);
end EvaluatedCapacitance;
