// Stream connectors (MLS 15): the rules that shape the flat equations.
// A set where one member's flow cannot enter (m_flow.min = 0) mixes only
// the others; a set of two outside connectors passes each one's inStream to
// the other (Bypass); stream arrays and arrays of connectors go element by
// element; the mixing's regularisation scales with the flows' nominal.
model StreamConnectors
  connector Port
    Real p;
    flow Real m_flow(nominal = 10);
    stream Real h_outflow;
    stream Real X_outflow[2];
  end Port;
  model Source
    parameter Real mdot = 1;
    parameter Real h = 100;
    Port port;
  equation
    port.m_flow = -mdot;
    port.h_outflow = h;
    port.X_outflow = {0.25, 0.75};
  end Source;
  model CheckValveInlet "fluid only enters here"
    Port port(m_flow(min = 0));
    Real h = inStream(port.h_outflow);
    Real X[2] = actualStream(port.X_outflow);
  equation
    port.h_outflow = 0;
    port.X_outflow = zeros(2);
  end CheckValveInlet;
  model Bypass "two outside connectors, nothing inside"
    Port a, b;
  equation
    connect(a, b);
  end Bypass;
  Source s[2](mdot = {1, 3}, h = {100, 200});
  Bypass bypass;
  CheckValveInlet inlet, other;
equation
  connect(s[1].port, bypass.a);
  connect(bypass.b, inlet.port);
  connect(s[2].port, inlet.port);
  connect(other.port, inlet.port);
  other.port.m_flow = 0;
  inlet.port.p = 1;
end StreamConnectors;
