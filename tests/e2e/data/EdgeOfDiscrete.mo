// A when-clause on the edge of a Boolean that an equation outside
// when-clauses defines, as the MSL's IdealSwitchWithArc writes it (`off = not
// control; when edge(off) then tSwitch = time; end when;`). The clause must
// fire in the event iteration where off changes: in the next one pre(off) is
// already true and the edge is gone. Exact: tSwitch = 0.5, count = 1 and
// x = (t - 0.5)^2/2 after 0.5.
model EdgeOfDiscrete
  Boolean control = time < 0.5;
  Boolean off(start = true, fixed = true);
  discrete Real tSwitch(start = -1e60, fixed = true);
  Integer count(start = 0, fixed = true);
  Real x(start = 0, fixed = true);
equation
  off = not control;
  when edge(off) then
    tSwitch = time;
    count = pre(count) + 1;
  end when;
  der(x) = if off then time - tSwitch else 0;
end EdgeOfDiscrete;
