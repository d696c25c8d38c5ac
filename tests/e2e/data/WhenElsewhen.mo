// when c0 then ... elsewhen c1 then ...: a branch's equations hold at an
// instant only if no earlier branch is activated there (Modelica 3 §8.3.5);
// "activated" is its condition becoming true, not its being true. A chain
// whose branches assign different variables is not Modelica (§8.3.5.2):
// Scilab's modelicac fires each branch that becomes true, and so do we.
model WhenElsewhen
  Real x(start = 0, fixed = true) "x = t";
  discrete Integer k(start = 0) "both branches activated at t = 0.5: the first's value, 1";
  discrete Integer n(start = 0) "+10 at t = 0.2; +1 at each tick of the sample, 0.3, 0.55 and 0.8";
  discrete Integer v(start = 0) "a vector branch: +1 at 0.6 and at 0.9, where the elsewhen is also activated";
  discrete Integer a(start = 0) "Scilab's rule: both branches activated at t = 0.4, a = 1";
  discrete Integer b(start = 0) "and b = 1";
equation
  der(x) = 1;
  when x >= 0.5 then
    k = 1;
  elsewhen x >= 0.5 then
    k = 2;
  end when;
  when x >= 0.2 then
    n = pre(n) + 10;
  elsewhen sample(0.3, 0.25) then
    n = pre(n) + 1;
  end when;
  when {x >= 0.6, x >= 0.9} then
    v = pre(v) + 1;
  elsewhen x >= 0.9 then
    v = 100;
  end when;
  when x >= 0.4 then
    a = 1;
  elsewhen x >= 0.4 then
    b = 1;
  end when;
end WhenElsewhen;
