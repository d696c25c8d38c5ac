// Time derivatives of the model's values for the initial system: der(y) in
// an initial equation of a variable y that the model computes but does not
// differentiate (the MSL's `der(aimc.idq_sr) = zeros(2)`, a steady state).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "mo/symbolic/ode.hpp"

namespace mo::symbolic::detail {

/// Unknowns and equations that define d/dt of some values at t0.
struct TimeDerivativeRows {
  std::vector<Expr> unknowns;                           ///< new symbols, each a derivative
  std::vector<std::pair<Expr, std::string>> equations;  ///< 0 = residual, and its origin
  bool input_reached = false;  ///< a value depends on an input (whose derivative is unknown)
};

/// For each (symbol d, value v) of `wanted`: d is an unknown with 0 = d − dv/dt.
/// dv/dt is taken through the model's steps: a state's derivative is its
/// Derivative symbol, time's is 1, parameters and discrete variables have
/// none, and a value a step computes gets an unknown `$d/dt(name)` with the
/// step differentiated (an assignment y = f: dy = df/dt; a block's
/// residuals: dr/dt = 0, for all its unknowns' derivatives), on demand, so
/// only the steps the wanted values depend on are differentiated.
TimeDerivativeRows time_derivative_rows(OdeModel& model, const std::vector<std::pair<Expr, Expr>>& wanted);

}  // namespace mo::symbolic::detail
