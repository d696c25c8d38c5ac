// when {a, b, c}: fires when any element becomes true (Modelica 3 §8.3.5),
// also when another element is already true (`or` would not fire then).
// Elements that become true together run the body once.
model WhenVector
  Real x(start = 0, fixed = true) "x = t";
  discrete Integer n(start = 0) "firings of the vector form";
  discrete Real last(start = -1) "time of the last firing";
  discrete Integer m(start = 0) "firings of the `or` form";
equation
  der(x) = 1;
  when {x > 0.3, x > 0.6, 0.3 < x} then
    n = pre(n) + 1;
    last = time;
  end when;
  when x > 0.3 or x > 0.6 then
    m = pre(m) + 1;
  end when;
end WhenVector;
