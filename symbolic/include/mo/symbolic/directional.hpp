// Directional derivatives through the steps of a lowered model, by the chain
// rule step by step (never by expanding f into one expression):
//
//   assignment  v := e(w)           dv := Σ ∂e/∂w · dw
//   block       0 = r(z, w)         J dz = -Σ ∂r/∂w · dw   (J = ∂r/∂z, the same
//                                   matrix as the block's: a linear block again)
//
// Only derivatives that are not identically zero get a symbol and a step, so
// the result is as sparse as the dependencies. This gives the forward
// sensitivity system (seeds = sensitivity states and a unit parameter
// direction) and Jacobian-vector products for code generation (seeds = seed
// symbols).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "mo/symbolic/ode.hpp"

namespace mo::symbolic {

/// The derivative of each step target along one direction.
struct Directional {
  std::vector<Step> steps;          ///< compute `symbols`, in order
  std::vector<OdeAlgebraic> symbols;  ///< the new Algebraic symbols
  /// Leaf → its derivative: the seeds, plus every step target whose derivative
  /// is not zero (a new symbol, or a constant/leaf when that is all it is).
  ExprMap derivative;
};

/// Names a derivative symbol after the name of the variable it differentiates.
using DerivativeNamer = std::function<std::string(const std::string& variable)>;

/// Differentiates model.steps along `seeds` (leaf → its derivative; leaves
/// not in `seeds` and not step targets have derivative 0). New symbols are
/// created in model.arena with names from `namer` (which must give names not
/// yet used); the model itself is not changed otherwise.
/// Throws std::invalid_argument if a seed key is not a leaf.
Directional differentiate_steps(OdeModel& model, const ExprMap& seeds,
                                const DerivativeNamer& namer);

/// The same for another step list of the model (e.g. model.initial_steps,
/// whose targets the start expressions use).
Directional differentiate_steps(OdeModel& model, const std::vector<Step>& steps,
                                const ExprMap& seeds, const DerivativeNamer& namer);

/// The derivative of `e` given a Directional's derivative map.
Expr derivative_along(OdeModel& model, const Directional& d, Expr e);

}  // namespace mo::symbolic
