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

// An initial equation on a variable that equals pre() values (the MSL's
// StateGraph.InitialStep: `active = true` with `active = localActive` and
// `localActive = pre(newActive)`) fixes those pre() values, whatever the
// order of the equations: pre(newActive) = true, then pre(localActive) and
// pre(oldActive) through `pre(newActive) = pre(localActive)`. Likewise
// `idle = false` with `idle = not pre(busy)` gives pre(busy) = true.
// Active until go at t = 0.5; oldActive keeps true from there.
model InitialStepChain
  Boolean active;
  Boolean localActive;
  Boolean newActive;
  Boolean oldActive;
  Boolean idle;
  Boolean busy;
  Boolean go = time > 0.5;
initial equation
  pre(newActive) = pre(localActive);
  pre(oldActive) = pre(localActive);
  active = true;
  idle = false;
equation
  active = localActive;
  localActive = pre(newActive);
  newActive = localActive and not go;
  when go then
    oldActive = localActive;
  end when;
  idle = not pre(busy);
  busy = pre(busy) and not go;
end InitialStepChain;

// Contradicting initial equations on pre() values: a diagnostic, not a run.
model InitialPreContradiction
  Boolean a;
  Boolean b;
initial equation
  pre(a) = true;
  pre(b) = pre(a);
  b = false;
equation
  a = pre(a);
  b = pre(b);
end InitialPreContradiction;
