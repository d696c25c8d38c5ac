// The MSL's Digital library where it calls delay() (TransportDelay): test_delays.cpp.
model Counter3Run
  extends Modelica.Electrical.Digital.Examples.Counter3;
end Counter3Run;
