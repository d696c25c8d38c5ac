// A stream variable connects only to a stream variable.
model ConnectStreamToPotential
  connector Port
    Real p;
    flow Real m;
    stream Real h;
  end Port;
  connector Plain
    Real p;
    flow Real m;
    Real h;
  end Plain;
  model A
    Port port;
  equation
    port.h = 1;
    port.p = 1;
  end A;
  model B
    Plain port;
  equation
    port.m = 0;
  end B;
  A a;
  B b;
equation
  connect(a.port, b.port);
end ConnectStreamToPotential;
