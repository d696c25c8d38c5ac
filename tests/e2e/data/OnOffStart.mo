// An on-off controller written as the MSL's OnOffController: a discrete
// equation outside when-clauses that reads pre(), with pre(y) = false at
// initialisation. The temperature starts below the band, so the heater is on
// from t0 (tests/e2e/test_initial_events.cpp). Exact until it reaches the
// band's top: T = T0 + heat*t.
model OnOffStart
  parameter Real reference = 25, bandwidth = 2, heat = 1, T0 = 20;
  Real T(start = T0, fixed = true);
  Boolean y;
equation
  y = T < reference - bandwidth/2 or pre(y) and T < reference + bandwidth/2;
  der(T) = if y then heat else -heat;
initial equation
  pre(y) = false;
end OnOffStart;
