// A mode flag set by initial() outside when-clauses, as the MSL's friction
// sets `startForward = initial() and w_relfric > 0 or …`: true during the
// initialisation, false again before the integration starts (the MSL's
// reference results show it false at t = 0). Exact: x(t) = 1 + t (a kick
// left on would give x' = 10).
model InitialFlagOutsideWhen
  Real x(start = 1, fixed = true);
  Boolean kick(start = false);
equation
  kick = initial() or pre(kick) and x > 2;
  der(x) = if kick then 10 else 1;
end InitialFlagOutsideWhen;
