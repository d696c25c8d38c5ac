// An if-equation inside a when-clause (the MSL's CombiTimeTable:
// `if next < DBL_MAX then nextTimeEvent = ... else nextTimeEvent = DBL_MAX`):
// each variable it assigns is one equation of the clause, its value an
// if-expression. Here b climbs by 2 at each event until it is held at 10:
// events at t = 2, 4, 6, 8 (b = 4, 6, 8, 10); at t = 10, time + p > 10 and
// b stays 10 while a keeps the time of each later event.
model WhenIf
  parameter Real p = 2;
  discrete Real a(start = 0, fixed = true);
  discrete Real b(start = 0, fixed = true);
equation
  when {time > pre(b), initial()} then
    a = time + p;
    if a < 10 then
      b = a;
    else
      b = 10;
    end if;
  end when;
end WhenIf;
