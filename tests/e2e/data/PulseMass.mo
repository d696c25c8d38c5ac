// A mass pushed by MoLib's rectangular Pulse: amplitude A during
// [startTime + k*period, startTime + k*period + width*period/100), else 0.
model PulseMass "Mass driven by a pulse force"
  parameter Real m = 2 "Mass (kg)";
  MoLib.Blocks.Sources.Pulse pulse(amplitude = 3, width = 30, period = 1, startTime = 0.25);
  Real x(start = 0, fixed = true) "Position (m)";
  Real v(start = 0, fixed = true) "Velocity (m/s)";
equation
  der(x) = v;
  m*der(v) = pulse.y.signal;
end PulseMass;
