// MoLib: a small Coselica-style component library for mocompile.
//
// Written in the Modelica 2.x subset that Scilab's translator `modelicat`
// accepts (see modelica/README.md): nested packages and full dotted names,
// no import/within, no type definitions, no short class definitions, no
// unit/min/max/stateSelect attributes, no Boolean/Integer variables, no
// inner/outer, no algorithm sections, no initial equations. Signals are
// connectors holding one `signal` variable, because `connector RealInput =
// input Real;` is rejected.
//
// Sign conventions follow the Modelica Standard Library: a flow variable is
// positive when it flows into the component (a flange force acts on the
// component), relative quantities are `flange_b - flange_a`.
//
// modelicat does NOT add `f = 0` for unconnected flow variables: every flange
// or frame of a model meant to be flattened must be connected (sensors set
// their own flow to zero).

package MoLib "Coselica-style components: translational, rotational, planar, signals"

  constant Real pi = 3.141592653589793;

  package Blocks "Signal blocks"

    package Interfaces
      connector RealInput "Real input signal (no prefix: see the file header)"
        Real signal;
      end RealInput;

      connector RealOutput "Real output signal (no prefix: see the file header)"
        Real signal;
      end RealOutput;

      partial block SO "Single output"
        MoLib.Blocks.Interfaces.RealOutput y;
      end SO;

      partial block SISO "Single input, single output"
        MoLib.Blocks.Interfaces.RealInput u;
        MoLib.Blocks.Interfaces.RealOutput y;
      end SISO;

      partial block SI2SO "Two inputs, single output"
        MoLib.Blocks.Interfaces.RealInput u1;
        MoLib.Blocks.Interfaces.RealInput u2;
        MoLib.Blocks.Interfaces.RealOutput y;
      end SI2SO;
    end Interfaces;

    package Sources
      block Constant "y = k"
        extends MoLib.Blocks.Interfaces.SO;
        parameter Real k = 1 "Constant output value";
      equation
        y.signal = k;
      end Constant;

      block Step "y = offset, plus height from startTime on"
        extends MoLib.Blocks.Interfaces.SO;
        parameter Real height = 1 "Height of step";
        parameter Real offset = 0 "Offset of output signal";
        parameter Real startTime = 0 "Output = offset for time < startTime";
      equation
        y.signal = offset + (if time < startTime then 0 else height);
      end Step;

      block Sine "y = offset + amplitude*sin(2*pi*freqHz*(time - startTime) + phase)"
        extends MoLib.Blocks.Interfaces.SO;
        parameter Real amplitude = 1 "Amplitude of sine wave";
        parameter Real freqHz = 1 "Frequency of sine wave (Hz)";
        parameter Real phase = 0 "Phase of sine wave (rad)";
        parameter Real offset = 0 "Offset of output signal";
        parameter Real startTime = 0 "Output = offset for time < startTime";
      equation
        y.signal = offset + (if time < startTime then 0 else
          amplitude*sin(2*MoLib.pi*freqHz*(time - startTime) + phase));
      end Sine;

      block Pulse "Periodic rectangular pulse; event-driven (when, pre)"
        extends MoLib.Blocks.Interfaces.SO;
        parameter Real amplitude = 1 "Amplitude of pulse";
        parameter Real width = 50 "Width of pulse in % of period";
        parameter Real period = 1 "Time for one period (s)";
        parameter Real offset = 0 "Offset of output signal";
        parameter Real startTime = 0 "Output = offset for time < startTime";
        // `sample` is not available in modelicat, so the start of the current
        // period is a discrete variable advanced by a when-equation. The
        // condition uses T0, not pre(T0): modelicac fails (assertion in its
        // code generator) on pre() inside a when condition.
        discrete Real T0(start = startTime) "Start time of the current period";
      equation
        when time >= T0 + period then
          T0 = pre(T0) + period;
        end when;
        y.signal = offset + (if time < startTime then 0 else
          (if time < T0 + width*period/100 then amplitude else 0));
      end Pulse;
    end Sources;

    package Math
      block Gain "y = k*u"
        extends MoLib.Blocks.Interfaces.SISO;
        parameter Real k = 1 "Gain";
      equation
        y.signal = k*u.signal;
      end Gain;

      block Add "y = k1*u1 + k2*u2"
        extends MoLib.Blocks.Interfaces.SI2SO;
        parameter Real k1 = 1 "Gain of input u1";
        parameter Real k2 = 1 "Gain of input u2";
      equation
        y.signal = k1*u1.signal + k2*u2.signal;
      end Add;
    end Math;
  end Blocks;

  package Mechanics

    package Translational "1D translational mechanics (s in m, f in N)"

      package Interfaces
        connector Flange "Translational flange"
          Real s "Absolute position of flange";
          flow Real f "Cut force into the component";
        end Flange;

        connector Flange_a "Left flange"
          extends MoLib.Mechanics.Translational.Interfaces.Flange;
        end Flange_a;

        connector Flange_b "Right flange"
          extends MoLib.Mechanics.Translational.Interfaces.Flange;
        end Flange_b;

        partial model Compliant "Two flanges, massless, force f between them"
          MoLib.Mechanics.Translational.Interfaces.Flange_a flange_a;
          MoLib.Mechanics.Translational.Interfaces.Flange_b flange_b;
          Real s_rel(start = 0) "Relative distance flange_b.s - flange_a.s";
          Real f "Force acting on flange_b (and -f on flange_a)";
        equation
          s_rel = flange_b.s - flange_a.s;
          flange_b.f = f;
          flange_a.f = -f;
        end Compliant;
      end Interfaces;

      package Components
        model Fixed "Flange fixed at position s0"
          parameter Real s0 = 0 "Fixed position";
          MoLib.Mechanics.Translational.Interfaces.Flange_b flange;
        equation
          flange.s = s0;
        end Fixed;

        model Mass "Sliding mass, s is the position of its centre"
          parameter Real m = 1 "Mass (kg)";
          parameter Real L = 0 "Length of the mass";
          MoLib.Mechanics.Translational.Interfaces.Flange_a flange_a;
          MoLib.Mechanics.Translational.Interfaces.Flange_b flange_b;
          Real s(start = 0) "Position of centre";
          Real v(start = 0) "Velocity";
          Real a(start = 0) "Acceleration";
        equation
          flange_a.s = s - L/2;
          flange_b.s = s + L/2;
          v = der(s);
          a = der(v);
          m*a = flange_a.f + flange_b.f;
        end Mass;

        model Damper "Linear viscous damper, f = d*der(s_rel)"
          extends MoLib.Mechanics.Translational.Interfaces.Compliant;
          parameter Real d = 0 "Damping constant (N.s/m)";
          Real v_rel(start = 0) "Relative velocity";
        equation
          v_rel = der(s_rel);
          f = d*v_rel;
        end Damper;

        model Spring "Linear spring, f = c*(s_rel - s_rel0)"
          extends MoLib.Mechanics.Translational.Interfaces.Compliant;
          parameter Real c = 1 "Spring constant (N/m)";
          parameter Real s_rel0 = 0 "Unstretched length";
        equation
          f = c*(s_rel - s_rel0);
        end Spring;

        model SpringDamper "Spring and damper in parallel"
          extends MoLib.Mechanics.Translational.Interfaces.Compliant;
          parameter Real c = 1 "Spring constant (N/m)";
          parameter Real d = 0 "Damping constant (N.s/m)";
          parameter Real s_rel0 = 0 "Unstretched length";
          Real v_rel(start = 0) "Relative velocity";
        equation
          v_rel = der(s_rel);
          f = c*(s_rel - s_rel0) + d*v_rel;
        end SpringDamper;
      end Components;

      package Sources
        model Force "Force f (input signal) acting on flange in +s direction"
          MoLib.Blocks.Interfaces.RealInput f "Driving force (N)";
          MoLib.Mechanics.Translational.Interfaces.Flange_b flange;
        equation
          flange.f = -f.signal;
        end Force;
      end Sources;

      package Sensors
        model PositionSensor "y = flange.s"
          MoLib.Mechanics.Translational.Interfaces.Flange_a flange;
          MoLib.Blocks.Interfaces.RealOutput s "Absolute position";
        equation
          flange.f = 0;
          s.signal = flange.s;
        end PositionSensor;

        model SpeedSensor "y = der(flange.s)"
          MoLib.Mechanics.Translational.Interfaces.Flange_a flange;
          MoLib.Blocks.Interfaces.RealOutput v "Absolute velocity";
        equation
          flange.f = 0;
          v.signal = der(flange.s);
        end SpeedSensor;
      end Sensors;
    end Translational;

    package Rotational "1D rotational mechanics (phi in rad, tau in N.m)"

      package Interfaces
        connector Flange "Rotational flange"
          Real phi "Absolute rotation angle of flange";
          flow Real tau "Cut torque into the component";
        end Flange;

        connector Flange_a "Left flange"
          extends MoLib.Mechanics.Rotational.Interfaces.Flange;
        end Flange_a;

        connector Flange_b "Right flange"
          extends MoLib.Mechanics.Rotational.Interfaces.Flange;
        end Flange_b;

        partial model Compliant "Two flanges, massless, torque tau between them"
          MoLib.Mechanics.Rotational.Interfaces.Flange_a flange_a;
          MoLib.Mechanics.Rotational.Interfaces.Flange_b flange_b;
          Real phi_rel(start = 0) "Relative angle flange_b.phi - flange_a.phi";
          Real tau "Torque acting on flange_b (and -tau on flange_a)";
        equation
          phi_rel = flange_b.phi - flange_a.phi;
          flange_b.tau = tau;
          flange_a.tau = -tau;
        end Compliant;
      end Interfaces;

      package Components
        model Fixed "Flange fixed at angle phi0"
          parameter Real phi0 = 0 "Fixed angle";
          MoLib.Mechanics.Rotational.Interfaces.Flange_b flange;
        equation
          flange.phi = phi0;
        end Fixed;

        model Inertia "Rotating inertia"
          parameter Real J = 1 "Moment of inertia (kg.m2)";
          MoLib.Mechanics.Rotational.Interfaces.Flange_a flange_a;
          MoLib.Mechanics.Rotational.Interfaces.Flange_b flange_b;
          Real phi(start = 0) "Absolute angle";
          Real w(start = 0) "Angular velocity";
          Real a(start = 0) "Angular acceleration";
        equation
          phi = flange_a.phi;
          phi = flange_b.phi;
          w = der(phi);
          a = der(w);
          J*a = flange_a.tau + flange_b.tau;
        end Inertia;

        model Damper "Linear rotational damper, tau = d*der(phi_rel)"
          extends MoLib.Mechanics.Rotational.Interfaces.Compliant;
          parameter Real d = 0 "Damping constant (N.m.s/rad)";
          Real w_rel(start = 0) "Relative angular velocity";
        equation
          w_rel = der(phi_rel);
          tau = d*w_rel;
        end Damper;

        model Spring "Linear torsional spring, tau = c*(phi_rel - phi_rel0)"
          extends MoLib.Mechanics.Rotational.Interfaces.Compliant;
          parameter Real c = 1 "Spring constant (N.m/rad)";
          parameter Real phi_rel0 = 0 "Unstretched angle";
        equation
          tau = c*(phi_rel - phi_rel0);
        end Spring;
      end Components;

      package Sources
        model Torque "Torque tau (input signal) acting on flange in +phi direction"
          MoLib.Blocks.Interfaces.RealInput tau "Driving torque (N.m)";
          MoLib.Mechanics.Rotational.Interfaces.Flange_b flange;
        equation
          flange.tau = -tau.signal;
        end Torque;
      end Sources;

      package Sensors
        model AngleSensor "y = flange.phi"
          MoLib.Mechanics.Rotational.Interfaces.Flange_a flange;
          MoLib.Blocks.Interfaces.RealOutput phi "Absolute angle";
        equation
          flange.tau = 0;
          phi.signal = flange.phi;
        end AngleSensor;
      end Sensors;
    end Rotational;

    package Planar "Planar multibody mechanics in the x-y plane, y up.
      Frame positions and cut forces are resolved in the world frame;
      phi is the absolute rotation of a frame about z."

      package Interfaces
        connector Frame "Planar frame: position, orientation, cut force and torque"
          Real x "x position of frame origin in world";
          Real y "y position of frame origin in world";
          Real phi "Rotation angle of frame w.r.t. world";
          flow Real fx "Cut force into the component, x (world)";
          flow Real fy "Cut force into the component, y (world)";
          flow Real t "Cut torque into the component";
        end Frame;

        connector Frame_a "Frame a"
          extends MoLib.Mechanics.Planar.Interfaces.Frame;
        end Frame_a;

        connector Frame_b "Frame b"
          extends MoLib.Mechanics.Planar.Interfaces.Frame;
        end Frame_b;
      end Interfaces;

      package Parts
        model World "The world frame at the origin (gravity is a Body parameter:
          modelicat has no inner/outer)"
          MoLib.Mechanics.Planar.Interfaces.Frame_b frame_b;
        equation
          frame_b.x = 0;
          frame_b.y = 0;
          frame_b.phi = 0;
        end World;

        model Fixed "Frame fixed in the world at (x0, y0, phi0)"
          parameter Real x0 = 0 "x position";
          parameter Real y0 = 0 "y position";
          parameter Real phi0 = 0 "Rotation angle";
          MoLib.Mechanics.Planar.Interfaces.Frame_b frame_b;
        equation
          frame_b.x = x0;
          frame_b.y = y0;
          frame_b.phi = phi0;
        end Fixed;

        model FixedTranslation "Massless rod from frame_a to frame_b; r resolved in frame_a"
          parameter Real rx = 1 "x component of r in frame_a";
          parameter Real ry = 0 "y component of r in frame_a";
          MoLib.Mechanics.Planar.Interfaces.Frame_a frame_a;
          MoLib.Mechanics.Planar.Interfaces.Frame_b frame_b;
          Real r0x "x component of r in world";
          Real r0y "y component of r in world";
        equation
          r0x = cos(frame_a.phi)*rx - sin(frame_a.phi)*ry;
          r0y = sin(frame_a.phi)*rx + cos(frame_a.phi)*ry;
          frame_b.x = frame_a.x + r0x;
          frame_b.y = frame_a.y + r0y;
          frame_b.phi = frame_a.phi;
          frame_a.fx + frame_b.fx = 0;
          frame_a.fy + frame_b.fy = 0;
          frame_a.t + frame_b.t + (r0x*frame_b.fy - r0y*frame_b.fx) = 0;
        end FixedTranslation;

        model Body "Rigid body: mass m, inertia I about the centre of mass,
          centre of mass at (rCMx, rCMy) from frame_a resolved in frame_a,
          uniform gravity (gx, gy) in world"
          parameter Real m = 1 "Mass (kg)";
          parameter Real I = 0.1 "Moment of inertia about the centre of mass (kg.m2)";
          parameter Real rCMx = 0 "Centre of mass from frame_a, x (in frame_a)";
          parameter Real rCMy = 0 "Centre of mass from frame_a, y (in frame_a)";
          parameter Real gx = 0 "Gravity acceleration, x (world)";
          parameter Real gy = -9.81 "Gravity acceleration, y (world)";
          MoLib.Mechanics.Planar.Interfaces.Frame_a frame_a;
          Real x(start = 0) "Centre of mass, x (world)";
          Real y(start = 0) "Centre of mass, y (world)";
          Real phi(start = 0) "Rotation angle";
          Real vx(start = 0) "Velocity of centre of mass, x";
          Real vy(start = 0) "Velocity of centre of mass, y";
          Real w(start = 0) "Angular velocity";
          Real ax "Acceleration of centre of mass, x";
          Real ay "Acceleration of centre of mass, y";
          Real z "Angular acceleration";
        equation
          x = frame_a.x + cos(frame_a.phi)*rCMx - sin(frame_a.phi)*rCMy;
          y = frame_a.y + sin(frame_a.phi)*rCMx + cos(frame_a.phi)*rCMy;
          phi = frame_a.phi;
          vx = der(x);
          vy = der(y);
          w = der(phi);
          ax = der(vx);
          ay = der(vy);
          z = der(w);
          // Newton and Euler (about the centre of mass); frame_a forces act on the body.
          m*(ax - gx) = frame_a.fx;
          m*(ay - gy) = frame_a.fy;
          I*z = frame_a.t + ((frame_a.x - x)*frame_a.fy - (frame_a.y - y)*frame_a.fx);
        end Body;
      end Parts;

      package Joints
        model Revolute "Revolute joint: frame_b = frame_a rotated by phi; viscous damping d"
          parameter Real d = 0 "Damping constant (N.m.s/rad)";
          MoLib.Mechanics.Planar.Interfaces.Frame_a frame_a;
          MoLib.Mechanics.Planar.Interfaces.Frame_b frame_b;
          Real phi(start = 0) "Relative rotation angle";
          Real w(start = 0) "Relative angular velocity";
        equation
          frame_b.x = frame_a.x;
          frame_b.y = frame_a.y;
          frame_b.phi = frame_a.phi + phi;
          w = der(phi);
          frame_a.fx + frame_b.fx = 0;
          frame_a.fy + frame_b.fy = 0;
          frame_a.t + frame_b.t = 0;
          // the torque acting on what hangs on frame_b is -frame_b.t = -d*w
          frame_b.t = d*w;
        end Revolute;

        model ActuatedRevolute "Revolute joint with rotational flanges:
          axis turns with frame_b, bearing with frame_a (both must be connected)"
          MoLib.Mechanics.Planar.Interfaces.Frame_a frame_a;
          MoLib.Mechanics.Planar.Interfaces.Frame_b frame_b;
          MoLib.Mechanics.Rotational.Interfaces.Flange_a axis "Drives the joint";
          MoLib.Mechanics.Rotational.Interfaces.Flange_b bearing "Housing, on frame_a";
          Real phi(start = 0) "Relative rotation angle";
          Real w(start = 0) "Relative angular velocity";
        equation
          frame_b.x = frame_a.x;
          frame_b.y = frame_a.y;
          frame_b.phi = frame_a.phi + phi;
          axis.phi = frame_b.phi;
          bearing.phi = frame_a.phi;
          w = der(phi);
          frame_a.fx + frame_b.fx = 0;
          frame_a.fy + frame_b.fy = 0;
          // torque on the axis is passed to frame_b, the reaction on the bearing to frame_a
          frame_b.t = -axis.tau;
          frame_a.t = -bearing.tau;
        end ActuatedRevolute;

        model ActuatedPrismatic "Prismatic joint along the unit direction (nx, ny) of frame_a,
          with translational flanges: axis moves with frame_b, bearing with frame_a
          (both must be connected); s = axis.s - bearing.s"
          parameter Real nx = 1 "Direction of the axis in frame_a, x";
          parameter Real ny = 0 "Direction of the axis in frame_a, y";
          MoLib.Mechanics.Planar.Interfaces.Frame_a frame_a;
          MoLib.Mechanics.Planar.Interfaces.Frame_b frame_b;
          MoLib.Mechanics.Translational.Interfaces.Flange_a axis "Drives the joint";
          MoLib.Mechanics.Translational.Interfaces.Flange_b bearing "Housing, on frame_a";
          Real s(start = 0) "Relative position along the axis";
          Real v(start = 0) "Relative velocity";
          Real ex "Axis direction in world, x";
          Real ey "Axis direction in world, y";
        equation
          ex = cos(frame_a.phi)*nx - sin(frame_a.phi)*ny;
          ey = sin(frame_a.phi)*nx + cos(frame_a.phi)*ny;
          s = axis.s - bearing.s;
          v = der(s);
          frame_b.x = frame_a.x + s*ex;
          frame_b.y = frame_a.y + s*ey;
          frame_b.phi = frame_a.phi;
          frame_a.fx + frame_b.fx = 0;
          frame_a.fy + frame_b.fy = 0;
          frame_a.t + frame_b.t + s*(ex*frame_b.fy - ey*frame_b.fx) = 0;
          // the force component along the axis is taken by the 1D flanges
          axis.f = -(ex*frame_b.fx + ey*frame_b.fy);
          bearing.f = -axis.f;
        end ActuatedPrismatic;
      end Joints;
    end Planar;
  end Mechanics;

end MoLib;
