// The textbook index-3 pendulum in Cartesian coordinates: position (x, y),
// velocity (vx, vy), rod force lambda, and the constraint x^2 + y^2 = L^2.
// Starts 30 degrees from hanging down, at rest.
model CartesianPendulum
  parameter Real L = 1 "Rod length (m)";
  parameter Real m = 1 "Mass (kg)";
  parameter Real g = 9.81 "Gravity (m/s2)";
  Real x(start = 0.5) "Horizontal position (m)";
  Real y(start = -0.8660254037844386) "Vertical position (m)";
  Real vx(start = 0) "Horizontal velocity (m/s)";
  Real vy(start = 0) "Vertical velocity (m/s)";
  Real lambda "Rod force per length (N/m)";
equation
  der(x) = vx;
  der(y) = vy;
  m*der(vx) = -lambda*x;
  m*der(vy) = -lambda*y - m*g;
  x^2 + y^2 = L^2;
end CartesianPendulum;
