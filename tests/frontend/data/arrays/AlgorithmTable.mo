// A Boolean table like the MSL's BooleanTable: an initial algorithm calls a
// function whose while-loop runs on a condition that varies (the start
// time), and a when statement advances a table index read by a subscript
// that varies in time.
function firstIndex
  input Real table[:];
  input Real t0;
  output Integer index;
  output Real nextTime;
protected
  Integer j = 1;
algorithm
  while j <= size(table, 1) and table[j] <= t0 loop
    j := j + 1;
  end while;
  if j > size(table, 1) then
    nextTime := 1e60;
  else
    nextTime := table[j];
  end if;
  index := j;
end firstIndex;

model AlgorithmTable
  parameter Real table[3] = {0.5, 1, 2};
  Integer index;
  Real nextTime;
  Boolean y(start = false);
initial algorithm
  (index, nextTime) := firstIndex(table, time);
  y := false;
algorithm
  when time >= pre(nextTime) then
    if index < 3 then
      index := index + 1;
      nextTime := table[index];
    else
      index := index + 1;
      nextTime := 1e60;
    end if;
    y := not y;
  end when;
end AlgorithmTable;
