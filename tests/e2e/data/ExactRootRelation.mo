// A mode flag defined by a relation outside when-clauses (as the MSL's
// friction defines startForward from sa > tau0_max). At the root CVODES
// reports, the indicator may be exactly 0: the flag must still take its new
// value there (tests/e2e/test_friction_modes.cpp).
model ExactRootRelation
  parameter Real limit = 0.5;
  Real x(start = 0, fixed = true);
  Boolean over(start = false);
  Integer crossings(start = 0);
equation
  der(x) = 1;
  over = pre(over) or x > limit;  // a latch: discrete, as it reads pre()
  when over then
    crossings = pre(crossings) + 1;
  end when;
end ExactRootRelation;
