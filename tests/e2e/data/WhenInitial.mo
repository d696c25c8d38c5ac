// when-clauses at initialisation: a clause on initial() fires at t0 (d = 2p,
// n = pre(n) + 1 with pre(n) = n.start), the others only when their
// condition becomes true later (e at t = 0.5, reading d as set at t0).
model WhenInitial
  parameter Real p = 3;
  discrete Real d(start = 1);
  discrete Real e(start = 5);
  Integer n(start = 4);
  Real x(start = 0, fixed = true) "x = d t = 6 t";
equation
  when initial() then
    d = 2*p;
    n = pre(n) + 1;
  end when;
  when time > 0.5 then
    e = pre(e) + d;
  end when;
  der(x) = d;
end WhenInitial;
