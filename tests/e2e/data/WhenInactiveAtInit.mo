// When-clauses at initialisation (Modelica 3 §8.6): one whose condition does
// not read initial() is inactive there, even if its condition becomes true
// during the event at initialisation (the MSL's BooleanNetwork1: a
// TriggeredAdd fed by change(u) with pre(u) = false); one that initial()
// enables fires once (tests/e2e/test_initial_events.cpp).
model WhenInactiveAtInit
  Boolean u;
  Boolean trig;
  Integer n(start = 0) "counts the changes of u after t0";
  Integer m(start = 0) "counts the initialisations";
equation
  u = time < 0.5;
  trig = change(u);
  when trig then
    n = pre(n) + 1;
  end when;
  when {initial(), trig} then
    m = pre(m) + 1;
  end when;
initial equation
  pre(u) = false;
end WhenInactiveAtInit;
