// Nonlinear blocks as unknowns of an optimiser instead of Newton iterations.
//
// Direct collocation (JModelica's approach) keeps the iteration variables of
// an algebraic loop as NLP unknowns at every collocation point and imposes the
// loop's residuals as equality constraints, so that no Newton iteration runs
// inside a model evaluation (where it can fail at the optimiser's trial
// points). This transform prepares an OdeModel for that: each nonlinear block
// `0 = r(z, ...)` solved for z (after tearing: the tearing variables) becomes
//   z_i := w_i          one assignment per unknown, w_i a new input,
//   r_k                 one new output per residual (to be held at 0),
// so f, h and every derivative of them see w as inputs: ∂r/∂w, ∂f/∂w are
// exact. Simulation of the transformed model needs w given; the model is
// meant for the optimiser only.
#pragma once

#include "mo/symbolic/ode.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace mo::symbolic {

/// One iteration variable turned into an input.
struct LoopInput {
  std::size_t input = 0;  ///< index into OdeModel::inputs of w
  std::string variable;   ///< name of the unknown z it sets
  double start = 0.0;     ///< the block's first Newton guess for z
  double min = -std::numeric_limits<double>::infinity();  ///< z's min attribute
  double max = std::numeric_limits<double>::infinity();   ///< z's max attribute
  double nominal = 1.0;   ///< z's nominal attribute
};

/// What expose_nonlinear_blocks changed.
struct LoopExposure {
  std::vector<LoopInput> inputs;      ///< one per iteration variable, in step order
  std::vector<std::size_t> residuals; ///< indices into OdeModel::outputs, to be 0
};

/// Replaces every nonlinear block of `model.steps` as described above. The new
/// inputs are named `$iteration(z)` and the residual outputs `$residual(z)` (z
/// the block's unknown of the same position). Linear blocks, the initial
/// system and when-clauses are unchanged. Returns an empty exposure for a
/// model without nonlinear blocks.
LoopExposure expose_nonlinear_blocks(OdeModel& model);

}  // namespace mo::symbolic
