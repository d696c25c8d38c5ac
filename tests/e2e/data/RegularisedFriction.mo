// A mass sliding backwards against friction written as the MSL's
// regularised sign (Translational's SignForce, reg = Exp):
// f = f0*(2/(1 + exp(-v/(0.01*v0))) - 1). At v = -5 m/s the exponent is
// 5e5: exp overflows, f is exactly -f0, but its derivative in v is
// inf/inf. The friction decelerates the mass at f0/m until v reaches 0.
model RegularisedFriction
  parameter Real m = 1, f0 = 5, v0 = 1e-3;
  Real v(start = -5, fixed = true);
  Real s(start = 0, fixed = true);
equation
  der(s) = v;
  m*der(v) = -f0*(2/(1 + exp(-v/(0.01*v0))) - 1);
end RegularisedFriction;
