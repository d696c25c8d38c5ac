model RegFun3Sweep
  "Modelica.Fluid.Utilities.regFun3 (nested ifs on its own intermediates) across its interval"
  parameter Real x0 = -1;
  parameter Real x1 = 2;
  parameter Real y0 = -2;
  parameter Real y1 = 3;
  parameter Real d0 = 0.5 "slope at x0";
  parameter Real d1 = 4 "slope at x1";
  Real x = x0 + (x1 - x0)*time "from x0 at t = 0 to x1 at t = 1";
  Real a = 0.2*sin(3*time) "moves every argument of the second call";
  Real y "end points and slopes of parameters";
  Real c;
  Real ya "varying end points and slopes";
  Real ca;
  Real yb "flat slopes: two cubics with a linear section";
  Real cb;
  Real z(start = 0, fixed = true) "the integral of y";
equation
  der(z) = y;
  (y, c) = Modelica.Fluid.Utilities.regFun3(x, x0, x1, y0, y1, d0, d1);
  (ya, ca) = Modelica.Fluid.Utilities.regFun3(x, x0 + a, x1 + a, y0 + a, y1 + a, d0 + a, d1 + a);
  (yb, cb) = Modelica.Fluid.Utilities.regFun3(x, x0, x1, y0, y1, 0.1 + a, 0.1);
end RegFun3Sweep;
