// Event indicators that read inputs: x crosses a moving threshold w(t) (the
// right-hand side switches there) and w(t) + v(t) (a reinit that reads v and
// x). The event time's derivative has the g_u u̇ term of the inputs' slopes:
// tests/e2e/test_event_sensitivities.cpp drives w by a table, v by a sine.
model InputCrossing
  input Real w "threshold";
  input Real v "offset of the reinit's threshold";
  parameter Real a = 1, b = 0.8, k = 2, c = 0.5;
  Real x(start = 0, fixed = true);
  Real y(start = 1, fixed = true);
equation
  der(x) = a - b*x + 0.6*sin(3*time);
  der(y) = if x > w then -k*y else c*x;
  when x > w + v then
    reinit(y, y + v + x);
  end when;
end InputCrossing;
