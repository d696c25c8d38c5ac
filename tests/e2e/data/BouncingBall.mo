// A ball dropped from h0 onto the floor; each impact reverses its velocity
// with restitution e. Peak height after the k-th bounce: e^(2k)*h0.
model BouncingBall "Bouncing ball with reinit"
  parameter Real g = 9.81 "Gravity (m/s2)";
  parameter Real e = 0.8 "Coefficient of restitution";
  parameter Real h0 = 1 "Drop height (m)";
  Real h(start = h0, fixed = true) "Height (m)";
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
