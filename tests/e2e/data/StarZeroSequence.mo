// A three-phase RL load in space phasors, star-connected with its star point
// left open, as the MSL's machines are: the star point says Σ i_k = 0 and the
// zero-sequence transformation −3·i0 = Σ i_k, so the zero-sequence
// inductor's current i0 is 0. Index reduction differentiates both; a choice of
// dummy derivatives by structure alone (i_1, i_2, i_3 and one space-phasor
// current) is numerically singular, since both equations fix the same sum.
// The space-phasor currents follow L·di/dt = V·e^{jωt} − R·i from rest.
model StarZeroSequence
  constant Real pi = 3.141592653589793;
  parameter Real V = 10, f = 50, R = 1, L = 0.01, L0 = 0.002;
  parameter Real T[2, 3] = 2/3*{{cos((k - 1)/3*2*pi) for k in 1:3},
                               {sin((k - 1)/3*2*pi) for k in 1:3}};
  Real i[3] "phase currents";
  Real iStar "current out of the open star point";
  Real i_[2](each start = 0, each fixed = true) "space-phasor current";
  Real i0 "zero-sequence current";
  Real v[3], v_[2], v0, vStar;
  Real vs[3] = {V*cos(2*pi*f*time - (k - 1)*2*pi/3) for k in 1:3};
  output Real iZero = i0;
  output Real iPhase1 = i[1];
equation
  sum(i) + iStar = 0;
  iStar = 0;
  -3*i0 = sum(i);
  i_ = T*i;
  v = vs - fill(vStar, 3);
  3*v0 = sum(v);
  v_ = T*v;
  L*der(i_) = v_ - R*i_;
  L0*der(i0) = v0;
end StarZeroSequence;
