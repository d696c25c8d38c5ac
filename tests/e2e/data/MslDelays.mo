// The MSL's blocks that call delay(): test_delays.cpp.
model Counter3Run  // Digital: TransportDelay closes each RS latch
  extends Modelica.Electrical.Digital.Examples.Counter3;
end Counter3Run;

model FixedDelayRun
  Modelica.Blocks.Sources.Sine sine(freqHz = 2);
  Modelica.Blocks.Nonlinear.FixedDelay d(delayTime = 0.1);
  output Real y = d.y;
equation
  connect(sine.y, d.u);
end FixedDelayRun;

model TLineRun  // a lossless line between matched resistors
  import Modelica.Electrical.Analog;
  Analog.Sources.SineVoltage src(V = 1, freqHz = 2);
  Analog.Basic.Resistor r1(R = 50);
  Analog.Basic.Resistor r2(R = 50);
  Analog.Lines.TLine1 line(Z0 = 50, TD = 0.1);
  Analog.Basic.Ground g;
  output Real y = r2.v;
equation
  connect(src.p, r1.p);
  connect(r1.n, line.p1);
  connect(line.p2, r2.p);
  connect(r2.n, g.p);
  connect(line.n2, g.p);
  connect(line.n1, g.p);
  connect(src.n, g.p);
end TLineRun;

model VariableDelayRun  // a delay time that grows from 0.1 to 0.2
  Modelica.Blocks.Sources.Sine sine(freqHz = 2);
  Modelica.Blocks.Sources.Ramp T(height = 0.1, duration = 1, offset = 0.1);
  Modelica.Blocks.Nonlinear.VariableDelay d(delayMax = 1);
  output Real y = d.y;
equation
  connect(sine.y, d.u);
  connect(T.y, d.delayTime);
end VariableDelayRun;
