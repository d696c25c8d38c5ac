// Statistics of a least-squares estimate: Fisher information from CVODES
// sensitivities, covariance, correlation, confidence intervals, warnings.
#pragma once

#include "mo/runtime/estimate.hpp"

namespace mo::runtime::detail {

/// Fills fisher … warnings of `result` (whose estimate and parameters are set).
/// On a failed sensitivity simulation the statistics stay empty and a warning says why.
void add_statistics(const Model& model, const EstimationProblem& problem, EstimationResult& result);

}  // namespace mo::runtime::detail
