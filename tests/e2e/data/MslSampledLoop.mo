// A sampled proportional loop of the MSL's blocks: a FirstOrder plant, a
// ZeroOrderHold of the error (its `when {sampleTrigger, initial()}` hold and
// `y = pre(ySample)`) and a Gain. Sensitivities through the hold are discrete
// sensitivities: tests/e2e/test_event_sensitivities.cpp.
model MslSampledLoop
  parameter Real k = 2 "controller gain";
  Modelica.Blocks.Continuous.FirstOrder plant(k = 1.5, T = 0.4,
    initType = Modelica.Blocks.Types.Init.InitialOutput, y_start = 0.1);
  Modelica.Blocks.Discrete.ZeroOrderHold hold(samplePeriod = 0.1, startTime = 0.2);
  Modelica.Blocks.Math.Feedback error;
  Modelica.Blocks.Math.Gain controller(k = k);
  Modelica.Blocks.Sources.Constant setPoint(k = 1);
equation
  connect(setPoint.y, error.u1);
  connect(plant.y, error.u2);
  connect(error.y, hold.u);
  connect(hold.y, controller.u);
  connect(controller.y, plant.u);
end MslSampledLoop;
