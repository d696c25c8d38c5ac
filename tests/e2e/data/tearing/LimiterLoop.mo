// A non-inverting amplifier on an idealised op-amp with output limits (as
// the MSL's IdealizedOpAmpLimted): the loop's residual in the feedback
// current i is a steep piece (gain V0) between two flat ones. Newton from
// the last solution cycles between the flat pieces once the input moves;
// the solution is vout = clamp(V0 v/(1 + V0/A), -15, 15), i = vout/(A R1).
model LimiterLoop
  parameter Real V0 = 15000 "open-loop gain";
  parameter Real A = 1.001 "closed-loop gain";
  parameter Real R1 = 10000;
  parameter Real f = 1000 "input frequency";
  Real v "input voltage";
  Real i(start = 0) "feedback current";
  Real vin "op-amp input voltage";
  output Real vout "output voltage";
  Real q(start = 0, fixed = true);
equation
  v = 20*sin(2*3.141592653589793*f*time);
  vin = v - R1*i;
  vout = A*R1*i;
  vout = smooth(0, min(15, max(-15, V0*vin)));
  der(q) = i;
end LimiterLoop;
