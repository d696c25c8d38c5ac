// A fed-batch yeast fermenter (Monod growth): biomass y1 [g/L] and substrate
// y2 [g/L], fed at dilution rate u1 [1/h] with substrate concentration u2
// [g/L]. Four kinetic parameters: maximum growth rate theta1, Monod constant
// theta2, yield theta3 and death rate theta4. The classic benchmark of
// optimal experiment design (Espie & Macchietto 1989; Asprey & Macchietto
// 2000), in the form of JModelica.org's OED example (fed_batch_oed.py).
model FedBatchReactor
  parameter Real theta1 = 0.1 "maximum specific growth rate [1/h]";
  parameter Real theta2 = 0.1 "Monod constant [g/L]";
  parameter Real theta3 = 0.1 "yield coefficient";
  parameter Real theta4 = 0.1 "specific death rate [1/h]";
  input Real u1 "dilution rate [1/h]";
  input Real u2 "substrate concentration of the feed [g/L]";
  Real y1(start = 7, fixed = true, min = 0) "biomass [g/L]";
  Real y2(start = 0, fixed = true, min = -0.1) "substrate [g/L]";
  Real rm "specific growth rate [1/h]";
equation
  rm = theta1 * y2 / (theta2 + y2);
  der(y1) = (rm - u1) * y1 - theta4 * y1;
  der(y2) = -rm * y1 / theta3 + u1 * (u2 - y2);
end FedBatchReactor;
