// A free final time by time scaling. With `finalTime(free = true, ...)` the
// study is solved on the normalised horizon τ ∈ [0, 1],
//
//     t = t0 + (tf − t0)·τ,   dx/dτ = (tf − t0)·f(x, u, p, t0 + (tf − t0)·τ),
//     ∫_{t0}^{tf} L dt = (tf − t0)·∫_0^1 L dτ,
//
// where tf is the free parameter `finalTime` (an NLP variable with its
// min/max, started from its initialGuess). The collocation grid is uniform
// (or `element_lengths`) in τ, so it stretches with tf; the model's exact
// derivatives and Hessians cover tf like any free parameter. Results are
// reported in real time again.
#pragma once

#include "mo/frontend/flat.hpp"
#include "mo/runtime/optimize.hpp"
#include "study_problem.hpp"

namespace mo::tools {

/// Rewrites every equation and initial equation of `flat` on τ: der(e) →
/// der(e)/(tf − t0) and time → t0 + (tf − t0)·time; multiplies the objective
/// integrand's output equation by (tf − t0). Call after add_problem_outputs
/// and add_bound_constraints, only when problem.free_final_time is set.
void scale_time(frontend::flat::Model& flat, const ProblemOutputs& problem);

/// The free final time's bounds in `p` raised to at least t0 (a horizon of
/// negative length has no meaning); `tf_index` is the parameter's index.
void bound_final_time(runtime::OptimalControlProblem& p, std::size_t tf_index, double t0);

/// `r` with times on τ mapped back to t = t0 + (tf − t0)·τ (trajectories,
/// re-simulation, element times, the check's worst times).
void rescale_result(runtime::OptimizationResult& r, double t0, double tf);

}  // namespace mo::tools
