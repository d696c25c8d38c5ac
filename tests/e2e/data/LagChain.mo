// A chain of n first-order lags driven by a unit step: state k is
//   x_k(t) = P(k, t/tau) = 1 - exp(-t/tau)·Σ_{j<k} (t/tau)^j/j!
// (the Erlang distribution's CDF), and dx_k/dtau = -(t/tau²)·exp(-t/tau)·
// (t/tau)^(k-1)/(k-1)! (its density times dλ/dtau). 150 states, at most two
// nonzeros per row of the Jacobian: large and sparse, so simulate() takes
// KLU (test_sparse_simulation.cpp).
model LagChain
  parameter Integer n = 150;
  parameter Real tau = 0.1;
  Real x[n](each start = 0, each fixed = true);
equation
  tau*der(x[1]) = 1 - x[1];
  for k in 2:n loop
    tau*der(x[k]) = x[k - 1] - x[k];
  end for;
end LagChain;
