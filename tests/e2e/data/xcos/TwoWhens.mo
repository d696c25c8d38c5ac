// One discrete variable set by two when-clauses (as Coselica's friction
// models do with Sticking): a triangle wave between 0 and 1.
model TwoWhens
  Real x(start = 0, fixed = true);
  discrete Real up(start = 1);
equation
  der(x) = if up > 0.5 then 1 else -1;
  when x > 1 then
    up = 0;
  end when;
  when x < 0 then
    up = 1;
  end when;
end TwoWhens;
