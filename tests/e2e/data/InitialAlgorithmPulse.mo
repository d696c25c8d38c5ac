// The MSL's Pulse (Modelica.Blocks.Sources.Pulse, 3.2.2) as written there:
// an `initial algorithm` gives the discrete period counter and the start of
// the current period their values at t0, and a when-clause on pre(count)
// counts periods. Started 2.5 periods before t0, the pulse is in the low half
// of its period at t0 (T_start = -0.5): y = 0 on [0, 0.5), 1 on [0.5, 1), ...
model InitialAlgorithmPulse
  parameter Real amplitude = 1;
  parameter Real width = 50 "in % of the period";
  parameter Real period = 1;
  parameter Real startTime = -2.5;
  Real y;
  Real x(start = 0, fixed = true) "integral of y";
protected
  Real T_width = period*width/100;
  Real T_start "start of the current period";
  Integer count "period count";
initial algorithm
  count := integer((time - startTime)/period);
  T_start := startTime + count*period;
equation
  when integer((time - startTime)/period) > pre(count) then
    count = pre(count) + 1;
    T_start = time;
  end when;
  y = if time < startTime then 0 else if time < T_start + T_width then amplitude else 0;
  der(x) = y;
end InitialAlgorithmPulse;
