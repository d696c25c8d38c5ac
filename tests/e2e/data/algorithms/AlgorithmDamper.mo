// An oscillator whose force is computed by an algorithm section: a variable
// assigned several times and read between, a for-loop accumulator, an `if`
// on a varying condition, and a table searched by a while-loop on a varying
// condition in a function with two outputs and a default argument.
function tableSearch "Piecewise-linear table, searched from iStart"
  input Real xs[:];
  input Real ys[size(xs, 1)];
  input Real x;
  input Integer iStart = 1;
  output Real y;
  output Integer i;
algorithm
  i := iStart;
  while i < size(xs, 1) - 1 and x >= xs[i + 1] loop
    i := i + 1;
  end while;
  y := ys[i] + (ys[i + 1] - ys[i]) * (x - xs[i]) / (xs[i + 1] - xs[i]);
end tableSearch;

model AlgorithmDamper
  parameter Real k = 2 "stiffness";
  parameter Real c = 0.1 "damping";
  parameter Real a = 1.5 "damping factor when moving backwards";
  parameter Real s = 1 "table scale";
  Real x(start = 2.5, fixed = true);
  Real v(start = 0, fixed = true);
  Real f "force";
  Real acc "damping force";
  Real g "table value";
  Integer segment "table segment of k*x";
algorithm
  f := -k * x;
  acc := 0;
  for j in 1:3 loop
    acc := acc + c * v / j;
  end for;
  if v > 0 then
    f := f - acc;
  else
    f := f - a * acc;
  end if;
  (g, segment) := tableSearch({-3, -1, 0, 1, 3}, {1, 0.25, 0, 0.25, 1}, s * x);
  f := f - g * v;
equation
  der(x) = v;
  der(v) = f;
end AlgorithmDamper;
