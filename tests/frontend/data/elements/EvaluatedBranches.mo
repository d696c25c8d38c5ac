// An if-expression whose condition reads only parameters marked
// Evaluate = true takes its branch when flattened, as Modelica.Fluid's start
// values need: T_start and h_start read each other, each in the branch its
// use_T_start does not take, and the function of the other branch (an
// iteration to a tolerance, evaluated at translation) would otherwise ask
// for h_start while h_start waits for T_start. A condition on a parameter
// without Evaluate keeps both branches.
model EvaluatedBranches
  function temperature "T with 4 T = h, by iteration"
    input Real h;
    output Real T = 0;
  algorithm
    while abs(4 * T - h) > 1e-9 loop
      T := T + (h - 4 * T) / 8;
    end while;
  end temperature;
  parameter Boolean use_T_start = true annotation(Evaluate = true);
  parameter Real T_start = if use_T_start then 300 else temperature(h_start);
  parameter Real h_start = if use_T_start then 4 * T_start else 1000;
  parameter Boolean flip = false "not evaluated: both branches stay";
  Real x(start = h_start, fixed = true);
  Real y = if flip then -x else x;
equation
  der(x) = -x;
end EvaluatedBranches;
