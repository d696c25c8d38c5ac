// inStream() takes a stream variable.
model InStreamNotStream
  connector Port
    Real p;
    flow Real m;
    Real h;
  end Port;
  Port port;
  Real h = inStream(port.h);
equation
  port.h = 1;
  port.p = 1;
end InStreamNotStream;
