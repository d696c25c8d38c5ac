// initial equation pre(y) = y_start of a discrete Boolean (the MSL's
// OnOffController and Logical.Pre): it fixes the value before the event at
// initialisation, not y. A heater with hysteresis between 0.2 and 0.8: with
// pre(y) = true it first heats from T = 0.5, with false it first cools.
model InitialPre
  parameter Boolean y_start = true "pre(y) at initial time";
  Real T(start = 0.5, fixed = true);
  Boolean y "heater on";
initial equation
  pre(y) = y_start;
equation
  y = pre(y) and T < 0.8 or T < 0.2;
  der(T) = if y then 1 else -1;
end InitialPre;

model InitialPreOff
  extends InitialPre(y_start = false);
end InitialPreOff;

// pre(b) set from pre(a) (the MSL's StateGraph: `pre(newActive) =
// pre(localActive)`): pre(a) is a's start, 3, so pre(b) = 4; at t = 0.5 the
// clause gives a = 4 and b = 2*pre(b) = 8.
model InitialPreChain
  discrete Real a(start = 3, fixed = true);
  discrete Real b;
initial equation
  pre(b) = pre(a) + 1;
equation
  when time > 0.5 then
    a = pre(a) + 1;
    b = 2*pre(b);
  end when;
end InitialPreChain;
