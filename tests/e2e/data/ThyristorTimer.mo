// A thyristor written as the MSL's IdealThyristor writes it (off = s < 0 or
// pre(off) and not fire), fired at the angle alpha of each positive half-wave
// by a timer written as the MSL's Logical.Timer (when u then entryTime = time),
// as the MSL's PowerConverters control does; a resistive load. At the start of
// a half-wave the timer's clause resets entryTime, and fire must read the new
// value: the thyristor conducts from alpha to pi only. Closed form:
// tests/e2e/test_events.cpp.
model ThyristorTimer
  constant Real pi = 3.141592653589793;
  parameter Real f = 50;
  parameter Real alpha = pi/6 "firing angle";
  parameter Real V = 100;
  parameter Real R = 10;
  parameter Real Ron = 1e-5;
  parameter Real Goff = 1e-5;
  Real v = V*sin(2*pi*f*time);
  Boolean u = v > 0 "positive half-wave";
  discrete Real entryTime(start = 0, fixed = true);
  Real y "time since the half-wave started";
  Boolean fire;
  Real s(start = 0);
  Boolean off(start = true, fixed = true);
  Real vd;
  output Real i;
  Real q(start = 0, fixed = true);
equation
  when u then
    entryTime = time;
  end when;
  y = if u then time - entryTime else 0;
  fire = y*2*pi*f > alpha;
  off = s < 0 or pre(off) and not fire;
  vd = s*(if off then 1 else Ron);
  i = s*(if off then Goff else 1);
  v = vd + R*i;
  der(q) = i;
end ThyristorTimer;
