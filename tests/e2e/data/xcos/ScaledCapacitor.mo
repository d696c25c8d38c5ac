// A capacitor whose voltage is a scaled, offset alias of a resistor current
// (vc = V - R*ir): the capacitor voltage must stay the state, starting at 0.
model ScaledCapacitor
  parameter Real R = 1000, C = 1e-3, V = 5;
  Real vc "capacitor voltage";
  Real ic, vr, ir;
equation
  C*der(vc) = ic;
  ic = ir;
  vr = R*ir;
  vc = V - vr;
end ScaledCapacitor;
