// Overdetermined connectors (MLS 9.4) in a small planar library of our own,
// written the way MultiBody writes its frames: the orientation is a record
// with an equalityConstraint function, joints declare Connections.branch,
// the ground Connections.root, bodies Connections.potentialRoot, and the
// equations depend on Connections.rooted / isRoot
// (tests/e2e/test_overconstrained.cpp).
package PlanarFrames
  record Orientation "planar orientation: the angle of the frame"
    Real phi;
    function equalityConstraint
      input Orientation R1;
      input Orientation R2;
      output Real residue[1];
    algorithm
      residue := {R1.phi - R2.phi};
    end equalityConstraint;
  end Orientation;

  connector Frame
    Real x;
    Real y;
    Orientation R;
    flow Real fx;
    flow Real fy;
    flow Real t;
  end Frame;

  model Ground
    Frame frame_b;
  equation
    Connections.root(frame_b.R);
    frame_b.x = 0;
    frame_b.y = 0;
    frame_b.R.phi = 0;
  end Ground;

  model Revolute "frictionless; phi turns frame_b against frame_a"
    parameter Real phi0 = 0;
    Frame frame_a;
    Frame frame_b;
    Real phi(start = phi0, fixed = true);
    Real w(start = 0, fixed = true);
    Boolean aRooted = Connections.rooted(frame_a.R);
  equation
    Connections.branch(frame_a.R, frame_b.R);
    if Connections.rooted(frame_a.R) then
      frame_b.R.phi = frame_a.R.phi + phi;
    else
      frame_a.R.phi = frame_b.R.phi - phi;
    end if;
    w = der(phi);
    frame_b.x = frame_a.x;
    frame_b.y = frame_a.y;
    frame_a.fx + frame_b.fx = 0;
    frame_a.fy + frame_b.fy = 0;
    frame_a.t + frame_b.t = 0;
    frame_a.t = 0;
  end Revolute;

  model Body "point mass m at L along the frame's x axis, inertia I about it"
    parameter Real m = 1;
    parameter Real I = 0.01;
    parameter Real L = 0.5;
    parameter Real g = 9.81;
    Frame frame_a;
    Real xc;
    Real yc;
    Boolean root = Connections.isRoot(frame_a.R);
  equation
    Connections.potentialRoot(frame_a.R);
    if Connections.isRoot(frame_a.R) then
      frame_a.R.phi = 0; // a body at the root holds its own orientation
    end if;
    xc = frame_a.x + L*cos(frame_a.R.phi);
    yc = frame_a.y + L*sin(frame_a.R.phi);
    m*der(der(xc)) = frame_a.fx;
    m*der(der(yc)) = frame_a.fy - m*g;
    I*der(der(frame_a.R.phi)) = frame_a.t + (frame_a.x - xc)*frame_a.fy - (frame_a.y - yc)*frame_a.fx;
  end Body;

  model Pendulum "ground - joint - body: the joint's frame_a is rooted"
    Ground ground;
    Revolute joint(phi0 = 0.3);
    Body body;
  equation
    connect(ground.frame_b, joint.frame_a);
    connect(joint.frame_b, body.frame_a);
  end Pendulum;

  model ReversedPendulum "the joint turned round: its frame_b is rooted, the body at -phi"
    Ground ground;
    Revolute joint(phi0 = -0.3);
    Body body;
  equation
    connect(ground.frame_b, joint.frame_b);
    connect(joint.frame_a, body.frame_a);
  end ReversedPendulum;

  model TwoJointsLoop "two joints in parallel between ground and body: a loop"
    Ground ground;
    Revolute joint1;
    Revolute joint2;
    Body body;
  equation
    connect(ground.frame_b, joint1.frame_a);
    connect(joint1.frame_b, body.frame_a);
    connect(ground.frame_b, joint2.frame_a);
    connect(joint2.frame_b, body.frame_a);
  end TwoJointsLoop;
end PlanarFrames;
