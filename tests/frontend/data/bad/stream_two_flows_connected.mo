// A stream connector with two flows, connected but never read by inStream:
// reported where the connection sets are built, not a crash.
model StreamTwoFlowsConnected
  connector Port
    Real p;
    flow Real m1;
    flow Real m2;
    stream Real h;
  end Port;
  model C
    Port port;
  equation
    port.h = 1;
  end C;
  model D
    Port a, b;
  equation
    connect(a, b);
  end D;
  C c1;
  D d;
equation
  connect(c1.port, d.a);
end StreamTwoFlowsConnected;
