// Two components joined by a port whose enthalpy flow is semiLinear of the
// mass flow in each (as the MSL's FluidHeatFlow writes them): where the mass
// flow is 0 the port's enthalpy h is left undetermined by the equations, and
// MLS 3.7.2.5 (rule 1) gives it the value upstream of the flow, with x >= 0
// taking the first component's partner. A source of enthalpy hA pushes the
// flow mdot into a mixing volume of enthalpy hB: 0 until t = 1, 1 until
// t = 2, then -1 (back into the source).
model SemiLinearZeroFlow
  connector Port
    flow Real m "mass flow into the component";
    flow Real H "enthalpy flow into the component";
    Real h "enthalpy at the port";
  end Port;
  model Source
    parameter Real hA = 2;
    input Real mdot;
    Port port;
  equation
    port.m = -mdot;
    port.H = semiLinear(port.m, port.h, hA);
  end Source;
  model Volume
    parameter Real M = 0.5 "mass";
    Real h(start = 1, fixed = true);
    Port port;
  equation
    M * der(h) = port.H - port.m * h;
    port.H = semiLinear(port.m, port.h, h);
  end Volume;
  Source source(mdot = if time < 1 then 0 else if time < 2 then 1 else -1);
  Volume volume;
equation
  connect(source.port, volume.port);
end SemiLinearZeroFlow;
