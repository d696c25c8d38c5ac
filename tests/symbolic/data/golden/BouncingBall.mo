// Events through lowering: a when-clause with reinit and a discrete counter.
model BouncingBall
  parameter Real e = 0.8 "Coefficient of restitution";
  parameter Real g = 9.81 "Gravity (m/s2)";
  Real h(start = 1, fixed = true) "Height (m)";
  Real v(start = 0, fixed = true) "Velocity (m/s)";
  Integer bounces(start = 0) "Number of bounces";
equation
  der(h) = v;
  der(v) = -g;
  when h < 0 then
    reinit(v, -e*pre(v));
    bounces = pre(bounces) + 1;
  end when;
end BouncingBall;
