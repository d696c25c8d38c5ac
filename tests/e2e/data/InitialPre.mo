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

// pre(above) = level_start >= h2, where h2 is no parameter but a variable
// that equations give from one (the MSL's AST_BatchPlant tank: a port height
// bound to a parameter record through an input connector and a connect()):
// the value at t0 follows, so pre(above) = (0.32 >= 0.3) = true. With the
// hysteresis of 0.05 the tank then drains fast (slope -1) until the level
// falls below 0.25 at t = 0.07, then slowly (-0.1); with pre(above) false it
// would drain slowly from the start.
model InitialPreFromVariables
  model Tank
    connector RealIn = input Real;
    parameter Real h_port = 0.3;
    parameter Real level_start = 0.32;
    RealIn h1 = 2*h_half;
    RealIn h2;
    Real h_half;
    Real rate "an equation that reads der(): gives nothing before the initial system";
    Real level(start = level_start, fixed = true);
    Boolean above;
  initial equation
    pre(above) = level_start >= h2;
  equation
    rate = 2*h_half + der(level);
    h_half = h_port/2;
    connect(h1, h2);
    above = level >= h2 + 0.05 or pre(above) and level >= h2 - 0.05;
    der(level) = if above then -1 else -0.1;
  end Tank;
  Tank tank;
end InitialPreFromVariables;

// The same equation on a variable that only the initial system gives (the
// level itself, whose start is not fixed): a diagnostic, not a guess.
model InitialPreFromUnknown
  Real level(start = 0.32);
  Boolean above;
initial equation
  der(level) = -1;
  pre(above) = level >= 0.3;
equation
  above = level >= 0.35 or pre(above) and level >= 0.25;
  der(level) = if above then -1 else -0.1 * level;
end InitialPreFromUnknown;
