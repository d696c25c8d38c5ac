// Evidence for the Xcos corpus diagram ControlledTemperature (issue 10; read
// with the corpus' flat file, ../shared/xcos-corpus/flat/ControlledTemperature.mo,
// which is not in this repository). The diagram closes its loop through three
// non-Modelica Scicos blocks; here they are written in Modelica with the
// parameters the diagram gives them (read with Scilab's importXcosDiagram):
//   CURV_f       the set point, linear between 10 points (rpar: x then y)
//   BIGSOM_f     e = set point - temperature (signs + and -)
//   HYSTHERESIS  high 2, low -2, outputs 1 and 0, zero crossings on: the
//                output becomes 1 when e rises above 2 and 0 when it falls
//                below -2, at the crossing instant
// The heater then runs ~10 ms at a time (400 K/s against 20 ms between
// Scilab's samples), so the recorded input column cannot place its switches;
// closed here, the model matches Scilab's run (tests/e2e/test_xcos_corpus.cpp).
model ControlledTemperatureLoop
  ControlledTemperature_imf plant;
  Real setpoint "CURV_f";
  Real e "BIGSOM_f";
  discrete Real on(start = 1) "HYSTHERESIS: e = 29 > 2 at t = 0";
equation
  setpoint =
    if time < -0.0508395 then 42.666667 + (48.66737 - 42.666667) * (time - (-0.7111111)) / (-0.0508395 - (-0.7111111))
    elseif time < 3.3777778 then 48.66737 + (73 - 48.66737) * (time - (-0.0508395)) / (3.3777778 - (-0.0508395))
    elseif time < 5.2888889 then 73 + (78.333333 - 73) * (time - (3.3777778)) / (5.2888889 - (3.3777778))
    elseif time < 8.2777778 then 78.333333 + (75.333333 - 78.333333) * (time - (5.2888889)) / (8.2777778 - (5.2888889))
    elseif time < 12 then 75.333333 + (68.333333 - 75.333333) * (time - (8.2777778)) / (12 - (8.2777778))
    elseif time < 15.833333 then 68.333333 + (64 - 68.333333) * (time - (12)) / (15.833333 - (12))
    elseif time < 19.555556 then 64 + (62.666667 - 64) * (time - (15.833333)) / (19.555556 - (15.833333))
    elseif time < 20.8 then 62.666667 + (62.666667 - 62.666667) * (time - (19.555556)) / (20.8 - (19.555556))
    elseif time < 23.555556 then 62.666667 + (62.666667 - 62.666667) * (time - (20.8)) / (23.555556 - (20.8))
    else 62.666667;
  e = setpoint - plant.`OutPutPort1.vo`;
  when e > 2 then
    on = 1;
  elsewhen e < -2 then
    on = 0;
  end when;
  plant.`InPutPort1.vi` = on;
end ControlledTemperatureLoop;
