// A hard stop as the MSL's MassWithStopAndFriction writes it: an Integer
// defined by a relation (no when, no pre), and a when-clause on it. The
// mass starts at 0 moving left at 1 against a push of 0.5 to the right; it
// reaches the stop at s = -0.4 at t1 = 2 (1 - sqrt(0.6)) ≈ 0.4508, where s
// and v are reinitialised, and then drifts back: s = -0.4 + (t - t1)²/4.
model HardStop
  Real s(start = 0, fixed = true);
  Real v(start = -1, fixed = true);
  Integer stopped;
equation
  der(s) = v;
  der(v) = 0.5;
  stopped = if s <= -0.4 then -1 else if s >= 0.4 then 1 else 0;
  when stopped <> 0 then
    reinit(s, if stopped < 0 then -0.4 else 0.4);
    reinit(v, 0);
  end when;
end HardStop;
