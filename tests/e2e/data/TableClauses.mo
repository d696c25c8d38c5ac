// A table stepped by a when-clause whose equations read each other (the new
// index gives the next time, as the MSL's IntegerTable writes it), and a
// counter in another clause on change() of the table's output (as the MSL's
// RadioButtonSource reads its BooleanTable). y steps to 10, 20, 30, 40 at
// t = 1, 2, 3, 4, and count follows it: 1, 2, 3, 4.
model TableClauses
  parameter Real times[4] = {1, 2, 3, 4};
  parameter Integer values[4] = {10, 20, 30, 40};
  discrete Real nextTime(start = 1, fixed = true);
  Integer index(start = 1, fixed = true);
  Integer y(start = 0, fixed = true);
  Integer count(start = 0, fixed = true);
equation
  when time >= pre(nextTime) then
    y = values[pre(index)];
    index = pre(index) + 1;
    nextTime = if index <= 4 then times[index] else time + 100;
  end when;
  when change(y) then
    count = pre(count) + 1;
  end when;
end TableClauses;
