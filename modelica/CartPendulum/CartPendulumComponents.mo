// Cart with pendulum (gantry crane) assembled from MoLib components, the way
// the paper builds it from Coselica blocks in Xcos (its Fig. 4).
//
//   translational:  fixed1 --damper1(d1)-- cart(m1) <-- force(F)
//                                           |
//   planar:  world -- prismatic(x) ------ axis/bearing
//                         | frame_b
//                      revolute  -- axis/bearing: damper2(d2)
//                         | frame_b
//                      rod: Body m2, I = m2*l^2/12 about its centre,
//                           centre at (0, -l/2) in the joint frame
//
// Why it reduces to CartPendulumODE (x = cart.s = prismatic.s,
// phi = revolute.phi; the rail does not rotate, so the rod's angle is phi):
//  * rod centre: xc = x + l/2*sin(phi), yc = -l/2*cos(phi); Newton on the rod
//    gives the hinge force on the rod (fx, fy) = m2*(der(vxc), der(vyc) + g).
//  * prismatic: axis.f = -frame_b.fx = fx, so the cart flange_b feels -fx;
//    force gives +F, damper1 gives -d1*v:  m1*der(v) = F - d1*v - fx, and with
//    der(vxc) = der(v) + l/2*(cos(phi)*der(w) - sin(phi)*w^2) this is row 1:
//    (m1 + m2)*der(v) + m2*l*cos(phi)/2*der(w) = m2*l*sin(phi)*w^2/2 - d1*v + F.
//  * revolute + damper2: axis.tau = -d2*w, so the joint torque on the rod is
//    -frame_b.t = -d2*w. Euler about the centre, I*der(w) = -d2*w + (hinge - centre) x (fx, fy),
//    expands with I + m2*l^2/4 = m2*l^2/3 to row 2:
//    m2*l*cos(phi)/2*der(v) + m2*l^2/3*der(w) = -m2*g*l*sin(phi)/2 - d2*w.

partial model CartPendulumComponentsBase "The plant without the force signal"
  parameter Real m1 = 2 "Equivalent cart mass (kg)";
  parameter Real d1 = 15 "Equivalent linear cart friction (N.s/m)";
  parameter Real m2 = 1 "Pendulum mass (kg)";
  parameter Real d2 = 0.5 "Rotational friction of the pendulum (N.m.s/rad)";
  parameter Real l = 0.5 "Pendulum length (m)";
  parameter Real g = 9.81 "Gravity (m/s2)";
  output Real y_x "Measured cart position (m)";
  output Real y_phi "Measured pendulum angle (rad)";
  MoLib.Mechanics.Planar.Parts.Fixed world "Rail origin";
  MoLib.Mechanics.Planar.Joints.ActuatedPrismatic prismatic(nx = 1, ny = 0) "Rail";
  MoLib.Mechanics.Translational.Components.Fixed fixed1 "Translational ground";
  MoLib.Mechanics.Translational.Components.Mass cart(m = m1, s(start = 0, fixed = true), v(start = 0, fixed = true));
  MoLib.Mechanics.Translational.Components.Damper damper1(d = d1) "Cart friction";
  MoLib.Mechanics.Translational.Sources.Force force;
  MoLib.Mechanics.Planar.Joints.ActuatedRevolute revolute(phi(start = 0, fixed = true), w(start = 0, fixed = true)) "Hinge";
  MoLib.Mechanics.Rotational.Components.Damper damper2(d = d2) "Hinge friction";
  MoLib.Mechanics.Planar.Parts.Body rod(m = m2, I = m2*l^2/12, rCMx = 0, rCMy = -l/2,
    gx = 0, gy = -g) "Uniform rod, hinged at one end";
  MoLib.Mechanics.Translational.Sensors.PositionSensor xSensor;
  MoLib.Mechanics.Rotational.Sensors.AngleSensor phiSensor;
equation
  connect(world.frame_b, prismatic.frame_a);
  connect(fixed1.flange, prismatic.bearing);
  connect(fixed1.flange, damper1.flange_a);
  connect(damper1.flange_b, cart.flange_a);
  connect(force.flange, cart.flange_a);
  connect(cart.flange_b, prismatic.axis);
  connect(cart.flange_b, xSensor.flange);
  connect(prismatic.frame_b, revolute.frame_a);
  connect(revolute.frame_b, rod.frame_a);
  connect(revolute.bearing, damper2.flange_a);
  connect(revolute.axis, damper2.flange_b);
  connect(revolute.axis, phiSensor.flange);
  y_x = xSensor.s.signal;
  y_phi = phiSensor.phi.signal;
end CartPendulumComponentsBase;

model CartPendulumComponents "Cart and pendulum from components, force input F"
  extends CartPendulumComponentsBase;
  input Real F "Force on the cart (N)";
equation
  force.f.signal = F;
end CartPendulumComponents;

model CartPendulumComponentsSine "Cart and pendulum from components, driven by a 3 N, 1 Hz Sine block"
  extends CartPendulumComponentsBase;
  MoLib.Blocks.Sources.Sine sine(amplitude = 3, freqHz = 1);
equation
  connect(sine.y, force.f);
end CartPendulumComponentsSine;

// Xcos-style variants: the diagram parameters declared `(fixed=false)` at
// top level, as Xcos writes them, so that the flat file keeps
// `parameter Real m1 = 2.` ... lines (plain parameters are inlined).
model CartPendulumComponentsPar "CartPendulumComponents with parameters kept by modelicat"
  extends CartPendulumComponents(m1(fixed = false), d1(fixed = false), m2(fixed = false),
    d2(fixed = false), l(fixed = false), g(fixed = false));
end CartPendulumComponentsPar;

model CartPendulumComponentsSinePar "CartPendulumComponentsSine with parameters kept by modelicat"
  extends CartPendulumComponentsSine(m1(fixed = false), d1(fixed = false), m2(fixed = false),
    d2(fixed = false), l(fixed = false), g(fixed = false));
end CartPendulumComponentsSinePar;
