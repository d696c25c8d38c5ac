// A relaxation oscillator: an integrator and a Schmitt trigger whose
// hysteresis is a nonlinear loop (positive feedback through a saturating
// amplifier, as the MSL's IdealizedOpAmpLimted writes it: min/max, no
// events). While y = Vs the branch exists as long as V0 (x + beta Vs) >= Vs;
// then y jumps to -Vs. Exact switching times: x(0) = 0 and |dx/dt| = Vs/tau
// give t1 = tau (beta - 1/V0), then every 2 tau (beta - 1/V0).
model SchmittOscillator
  parameter Real Vs = 10 "saturation";
  parameter Real V0 = 1000 "amplification";
  parameter Real beta = 0.5 "positive feedback";
  parameter Real tau = 0.01 "integrator time constant";
  Real x(start = 0, fixed = true) "integrator output";
  output Real y(start = Vs) "trigger output";
equation
  tau * der(x) = -y;
  y = min(Vs, max(-Vs, V0 * (x + beta * y)));
end SchmittOscillator;
