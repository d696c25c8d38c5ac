// Examples of the MSL's MultiBody library, unchanged (needs Modelica 3.2.2
// on the library path): overdetermined frame connectors with
// Connections.root / branch / potentialRoot, quaternion types, functions
// called through the world component (tests/e2e/test_overconstrained.cpp).

// A body of 1 kg, its centre of mass 0.5 m out, on a revolute joint about z
// with a damper of 0.1 N.m.s/rad, released at rest horizontally under
// gravity along -y.
model Pendulum
  extends Modelica.Mechanics.MultiBody.Examples.Elementary.Pendulum;
end Pendulum;

// Two free bodies (point masses, r_CM = 0) in the point gravity field of
// mue = 1: each flies its Kepler orbit, each body its own root of the
// connection graph (Connections.isRoot: its states).
model PointGravity
  extends Modelica.Mechanics.MultiBody.Examples.Elementary.PointGravity;
end PointGravity;

// A free body hung from the world by three line-force springs, two of them
// in series with a massless point between them (iterated on: the point's
// position, whose start the example gives); no damping, so the body's
// kinetic energy plus gravity's and the springs' potential is conserved.
model ThreeSprings
  extends Modelica.Mechanics.MultiBody.Examples.Elementary.ThreeSprings;
end ThreeSprings;

// Three planar loops closed analytically by JointRRR assemblies, driven by a
// prescribed sine angle: each joint's axis n_b (fixed = false, Evaluate =
// true) and branch of the loop's solution (a Boolean fixed = false) are
// computed by its initial equations.
model PlanarLoops_analytic
  extends Modelica.Mechanics.MultiBody.Examples.Loops.PlanarLoops_analytic;
end PlanarLoops_analytic;
