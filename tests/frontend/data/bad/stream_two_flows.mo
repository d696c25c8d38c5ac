// A stream connector has exactly one flow variable to carry its streams.
model StreamTwoFlows
  connector Port
    Real p;
    flow Real m1;
    flow Real m2;
    stream Real h;
  end Port;
  Port port;
  Real h = actualStream(port.h);
equation
  port.h = 1;
  port.p = 1;
end StreamTwoFlows;
