// Stream connectors (MLS 15) in three systems whose enthalpies have closed
// forms. Each tank is well mixed with a constant mass M and specific
// enthalpy h = U/M; der(U) sums m_flow * actualStream(h_outflow) over its
// ports.
package StreamMixing
  connector Port
    Real p;
    flow Real m_flow "> 0 into the component";
    stream Real h_outflow "h near the port if fluid flows out";
  end Port;

  model Source "a fixed flow into the system at a fixed enthalpy"
    parameter Real mdot;
    parameter Real h;
    Port port;
  equation
    port.m_flow = -mdot;
    port.h_outflow = h;
  end Source;

  model Sink "draws mdot; never gives fluid back"
    parameter Real mdot;
    Port port(m_flow(min = 0));
    Real h_in = inStream(port.h_outflow);
  equation
    port.m_flow = mdot;
    port.h_outflow = 0;
  end Sink;

  model Boundary "a prescribed flow q(t) = sin(t) into the system, at hb when it enters"
    parameter Real hb = 50;
    Port port;
  equation
    port.m_flow = -sin(time);
    port.h_outflow = hb;
    port.p = 1;
  end Boundary;

  model Tank
    parameter Real M = 2;
    parameter Real p0 = 1;
    Real U(start = 0, fixed = true);
    Real h = U / M;
    Port a, b;
  equation
    der(U) = a.m_flow * actualStream(a.h_outflow) + b.m_flow * actualStream(b.h_outflow);
    a.h_outflow = h;
    b.h_outflow = h;
    b.p = a.p;
  end Tank;

  model PressureTank "a tank that sets its pressure"
    extends Tank;
  equation
    a.p = p0;
  end PressureTank;

  model Pipe "isenthalpic, no pressure drop"
    Port a, b;
  equation
    a.m_flow + b.m_flow = 0;
    a.p = b.p;
    a.h_outflow = inStream(b.h_outflow);
    b.h_outflow = inStream(a.h_outflow);
  end Pipe;

  model Line "a pipe seen through the line's own ports (one inside, one outside connector per set)"
    Port a, b;
    Pipe pipe;
  equation
    connect(a, pipe.a);
    connect(pipe.b, b);
  end Line;

  model Mixer "three outside connectors joined: out carries the mixing of a and b"
    Port a, b, out;
  equation
    connect(a, out);
    connect(b, out);
  end Mixer;

  model Junction "three inside connectors: two sources and a tank's inlet; a still source adds nothing"
    Source s1(mdot = 1, h = 100), s2(mdot = 3, h = 200), s0(mdot = 0, h = 1000);
    PressureTank tank;
    Sink sink(mdot = 4);
  equation
    connect(s1.port, tank.a);
    connect(s2.port, tank.a);
    connect(s0.port, tank.a);
    connect(tank.b, sink.port);
  end Junction;

  model Hierarchy "the same flows through a mixer and a line of nested outside connectors"
    Source s1(mdot = 1, h = 100), s2(mdot = 3, h = 200);
    Mixer mixer;
    Line line;
    PressureTank tank;
    Sink sink(mdot = 4);
    Real h_mixed = actualStream(line.a.h_outflow) "the enthalpy entering the line";
  equation
    connect(s1.port, mixer.a);
    connect(s2.port, mixer.b);
    connect(mixer.out, line.a);
    connect(line.b, tank.a);
    connect(tank.b, sink.port);
  end Hierarchy;

  model Reversal "a flow that enters, then leaves: actualStream switches at t = pi"
    Boundary boundary;
    Tank tank "port b unconnected: no flow, inStream(b) = b";
    Real h_b = inStream(tank.b.h_outflow);
  equation
    connect(boundary.port, tank.a);
  end Reversal;
end StreamMixing;
