// Cart with pendulum (gantry crane), written as equations: see
// shared docs cart-pendulum.md and the paper's eq. (9).
// States x (cart position), phi (pendulum angle, 0 = hanging down),
// v = der(x), w = der(phi). Input F pushes the cart in +x.
// Outputs y = (x, phi) as y_x, y_phi. All states are 0 at t = 0 (fixed).

model CartPendulumODE "Cart and pendulum, mass-matrix form, force input F"
  parameter Real m1(unit = "kg") = 2 "Equivalent cart mass (kg)";
  parameter Real d1(unit = "N.s/m") = 15 "Equivalent linear cart friction (N.s/m)";
  parameter Real m2(unit = "kg") = 1 "Pendulum mass (kg)";
  parameter Real d2(unit = "N.m.s/rad") = 0.5 "Rotational friction of the pendulum (N.m.s/rad)";
  parameter Real l(unit = "m") = 0.5 "Pendulum length (m)";
  parameter Real g(unit = "m/s2") = 9.81 "Gravity (m/s2)";
  input Real F(unit = "N") "Force on the cart (N)";
  output Real y_x(unit = "m") "Measured cart position (m)";
  output Real y_phi(unit = "rad") "Measured pendulum angle (rad)";
  Real x(unit = "m", start = 0, fixed = true) "Cart position (m)";
  Real phi(unit = "rad", start = 0, fixed = true) "Pendulum angle, 0 = hanging down (rad)";
  Real v(unit = "m/s", start = 0, fixed = true) "Cart velocity (m/s)";
  Real w(unit = "rad/s", start = 0, fixed = true) "Pendulum angular velocity (rad/s)";
equation
  der(x) = v;
  der(phi) = w;
  (m1 + m2)*der(v) + m2*l*cos(phi)/2*der(w) = m2*l*sin(phi)*w^2/2 - d1*v + F;
  m2*l*cos(phi)/2*der(v) + m2*l^2/3*der(w) = -m2*g*l*sin(phi)/2 - d2*w;
  y_x = x;
  y_phi = phi;
end CartPendulumODE;

// The simulation check of the paper (Fig. 5): F = 3 sin(2 pi 1 t).
// Written out in full (not extends) so that F is an ordinary variable here
// and the flat names (x, phi, v, w) are the same as in CartPendulumODE.
model CartPendulumSine "Cart and pendulum driven by F = 3*sin(2*pi*1*time)"
  parameter Real m1(unit = "kg") = 2 "Equivalent cart mass (kg)";
  parameter Real d1(unit = "N.s/m") = 15 "Equivalent linear cart friction (N.s/m)";
  parameter Real m2(unit = "kg") = 1 "Pendulum mass (kg)";
  parameter Real d2(unit = "N.m.s/rad") = 0.5 "Rotational friction of the pendulum (N.m.s/rad)";
  parameter Real l(unit = "m") = 0.5 "Pendulum length (m)";
  parameter Real g(unit = "m/s2") = 9.81 "Gravity (m/s2)";
  parameter Real A(unit = "N") = 3 "Force amplitude (N)";
  parameter Real f(unit = "Hz") = 1 "Force frequency (Hz)";
  Real F(unit = "N") "Force on the cart (N)";
  output Real y_x(unit = "m") "Measured cart position (m)";
  output Real y_phi(unit = "rad") "Measured pendulum angle (rad)";
  Real x(unit = "m", start = 0, fixed = true) "Cart position (m)";
  Real phi(unit = "rad", start = 0, fixed = true) "Pendulum angle, 0 = hanging down (rad)";
  Real v(unit = "m/s", start = 0, fixed = true) "Cart velocity (m/s)";
  Real w(unit = "rad/s", start = 0, fixed = true) "Pendulum angular velocity (rad/s)";
equation
  F = A*sin(2*3.141592653589793*f*time);
  der(x) = v;
  der(phi) = w;
  (m1 + m2)*der(v) + m2*l*cos(phi)/2*der(w) = m2*l*sin(phi)*w^2/2 - d1*v + F;
  m2*l*cos(phi)/2*der(v) + m2*l^2/3*der(w) = -m2*g*l*sin(phi)/2 - d2*w;
  y_x = x;
  y_phi = phi;
end CartPendulumSine;

// Xcos-style variants: Xcos declares diagram parameters as
// `parameter Real p(fixed=false) = value`; only then does modelicat keep
// `parameter Real` lines in the flat file (plain parameters are inlined).
model CartPendulumODEPar "CartPendulumODE with parameters kept by modelicat"
  extends CartPendulumODE(m1(fixed = false), d1(fixed = false), m2(fixed = false),
    d2(fixed = false), l(fixed = false), g(fixed = false));
end CartPendulumODEPar;

model CartPendulumSinePar "CartPendulumSine with parameters kept by modelicat"
  extends CartPendulumSine(m1(fixed = false), d1(fixed = false), m2(fixed = false),
    d2(fixed = false), l(fixed = false), g(fixed = false), A(fixed = false), f(fixed = false));
end CartPendulumSinePar;
