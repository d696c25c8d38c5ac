// Small models that use every MoLib component not used by the cart-pendulum,
// to check that each flattens to a balanced model (modelicat) that Scilab's
// modelicac can compile; scripts/make-flat-models.sh does both (in a scratch
// folder: no flat files of these are committed).

package MoLibExamples

  model SpringMassPulse "Mass on a spring-damper, pushed by pulses: Constant + Gain(Pulse) via Add"
    MoLib.Mechanics.Translational.Components.Fixed fixed(s0 = 0);
    MoLib.Mechanics.Translational.Components.SpringDamper sd(c = 100, d = 2, s_rel0 = 0.1);
    MoLib.Mechanics.Translational.Components.Spring spring(c = 50, s_rel0 = 0.2);
    MoLib.Mechanics.Translational.Components.Mass mass(m = 1, L = 0.05, s(start = 0.1, fixed = true), v(start = 0, fixed = true));
    MoLib.Mechanics.Translational.Sources.Force force;
    MoLib.Mechanics.Translational.Sensors.SpeedSensor speed;
    MoLib.Mechanics.Translational.Sensors.PositionSensor position;
    MoLib.Blocks.Sources.Pulse pulse(amplitude = 1, width = 30, period = 0.5, startTime = 0.2);
    MoLib.Blocks.Sources.Constant bias(k = -0.5);
    MoLib.Blocks.Math.Gain gain(k = 4);
    MoLib.Blocks.Math.Add add(k1 = 1, k2 = 1);
  equation
    connect(fixed.flange, sd.flange_a);
    connect(fixed.flange, spring.flange_a);
    connect(sd.flange_b, mass.flange_a);
    connect(mass.flange_b, spring.flange_b);
    connect(force.flange, mass.flange_b);
    connect(speed.flange, mass.flange_b);
    connect(position.flange, mass.flange_a);
    connect(pulse.y, gain.u);
    connect(gain.y, add.u1);
    connect(bias.y, add.u2);
    connect(add.y, force.f);
  end SpringMassPulse;

  model RotationalStep "Torque step on an inertia held by a torsional spring and damper"
    MoLib.Mechanics.Rotational.Components.Fixed fixed;
    MoLib.Mechanics.Rotational.Components.Spring spring(c = 10);
    MoLib.Mechanics.Rotational.Components.Damper damper(d = 0.3);
    MoLib.Mechanics.Rotational.Components.Inertia inertia(J = 0.1, phi(start = 0, fixed = true), w(start = 0, fixed = true));
    MoLib.Mechanics.Rotational.Sources.Torque torque;
    MoLib.Mechanics.Rotational.Sensors.AngleSensor angle;
    MoLib.Blocks.Sources.Step step(height = 2, startTime = 0.1);
  equation
    connect(fixed.flange, spring.flange_a);
    connect(fixed.flange, damper.flange_a);
    connect(spring.flange_b, inertia.flange_a);
    connect(damper.flange_b, inertia.flange_a);
    connect(torque.flange, inertia.flange_b);
    connect(angle.flange, inertia.flange_b);
    connect(step.y, torque.tau);
  end RotationalStep;

  model PlanarPendulum "Damped pendulum: world, revolute, massless rod, point-like body at its end"
    MoLib.Mechanics.Planar.Parts.World world;
    MoLib.Mechanics.Planar.Joints.Revolute revolute(d = 0.1, phi(start = 1, fixed = true), w(start = 0, fixed = true));
    MoLib.Mechanics.Planar.Parts.FixedTranslation rod(rx = 0, ry = -1);
    MoLib.Mechanics.Planar.Parts.Body bob(m = 1, I = 0.01);
  equation
    connect(world.frame_b, revolute.frame_a);
    connect(revolute.frame_b, rod.frame_a);
    connect(rod.frame_b, bob.frame_a);
  end PlanarPendulum;
end MoLibExamples;
