// A pulse as the MSL's BooleanPulse writes it (a sampled start time and a
// Boolean defined by relations on time) counted by a when-clause, as its
// TriggeredAdd does. At each tick the start time becomes the time, so the
// indicator time - pulseStart is exactly 0 and then leaves 0 upwards: that
// is no rising edge of y (y was already true at 0). One count per period:
// count = floor(t) for t >= 1.
model PulseCount
  discrete Real pulseStart(start = 0, fixed = true);
  Boolean y;
  Integer count(start = 0, fixed = true);
equation
  when sample(0, 1) then
    pulseStart = time;
  end when;
  y = time >= pulseStart and time < pulseStart + 0.5;
  when y then
    count = pre(count) + 1;
  end when;
end PulseCount;
