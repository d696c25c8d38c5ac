// Optimal input design (design of experiments) for parameter precision.
//
//   F(u) = Σ_k S_y(t_k)ᵀ Σ⁻¹ S_y(t_k),   S_y = ∂h/∂x · S_x + ∂h/∂p_J  (measured rows),
//
// where S_x = ∂x/∂p_J are the model's own sensitivity states (StateVariable::
// sensitivity, appended by the compiler) and ∂h/∂x, ∂h/∂p come from the model's
// output Jacobians, Σ = diag(σ²) over the measured outputs, t_k the measurement
// times, J the parameters of interest. The input maximises a criterion of F
// subject to the optimal control problem's dynamics, bounds and constraints:
//   A: min trace F⁻¹   T: max trace F   D: max log det F   E: max λ_min(F)
// (E via an epigraph variable s and F − s·I = L·Lᵀ with L lower triangular).
// When the model has the output sensitivities d(y)/d(p) and provides Hessians
// (every generated model does), F's entries are NLP variables defined by
// equality rows, and the Lagrangian Hessian is exact and sparse
// (docs/design-formulation.md); otherwise, or with HessianMode::limited_memory,
// the criterion is a function of the trajectory and Ipopt's L-BFGS is used.
#pragma once

#include <functional>

#include "mo/runtime/optimize.hpp"

#include <Eigen/Dense>

namespace mo::runtime {

/// Which scalar of the Fisher matrix is optimised.
enum class DesignCriterion {
  A,  ///< minimise trace F⁻¹ (the A-criterion proper)
  T,  ///< maximise trace F (the paper's "A-criterion")
  D,  ///< maximise log det F
  E,  ///< maximise the smallest eigenvalue of F
};

/// What is measured, when, and how noisily.
struct MeasurementDesign {
  std::vector<std::size_t> outputs;  ///< measured model outputs
  std::vector<double> sigma;         ///< noise standard deviation per measured output, > 0
  std::vector<double> times;         ///< measurement instants within [t0, tf]

  /// t0 + k·(tf − t0)/count for k = 1..count (the samples of a uniform sampler).
  static std::vector<double> uniform_times(double t0, double tf, std::size_t count);
};

/// An input-design problem: an optimal control problem plus the information measure.
struct InputDesignProblem {
  /// Dynamics, controls, bounds, constraints and discretisation; its Mayer and
  /// Lagrange terms, if any, are added to the criterion (e.g. as regularisation).
  OptimalControlProblem ocp;
  std::vector<std::size_t> parameters;  ///< J: parameters of interest (need sensitivity states)
  MeasurementDesign measurements;       ///< measured outputs, σ, times
  DesignCriterion criterion = DesignCriterion::T;  ///< what to optimise
  /// Initial guesses of the first control to try in turn (several local optima
  /// exist); empty means the problem's own guess only. The best result is kept.
  std::vector<std::shared_ptr<const InputSignal>> starts;
  /// Called before each of several starts with (k, number of starts, best
  /// information so far or NaN), k from 0; for progress reports. May be empty.
  std::function<void(std::size_t, std::size_t, double)> on_start;
  /// When an exact-Hessian solve ends without converging (iteration_limit,
  /// restoration_failure, stalled), solve once more with the limited-memory
  /// Hessian from the same start and keep that result if it converges
  /// (docs/design-formulation.md, "Fallback").
  bool hessian_fallback = true;
};

/// One solve of a design from one start: the exact-Hessian solve and, after
/// its failure, the limited-memory fallback.
struct DesignAttempt {
  HessianMode hessian = HessianMode::exact;  ///< exact or limited_memory (what the solve began with)
  OptimizationStatus status = OptimizationStatus::solver_error;  ///< how it ended
  int iterations = 0;                    ///< Ipopt iterations of its last solve
  KktResiduals kkt;                      ///< residuals of its returned point
  double solve_seconds = 0.0;            ///< Ipopt time, its retries included
  double information_collocation = 0.0;  ///< criterion of its F in collocation
  double information_resimulated = 0.0;  ///< criterion of its replayed F (NaN on failure)
  bool kept = false;                     ///< its result is the one returned
};

/// The designed input with its Fisher information, in collocation and replayed.
struct InputDesignResult {
  OptimizationResult optimization;    ///< the best start's optimisation result
  Eigen::MatrixXd fisher_collocation;  ///< F of the collocation solution
  Eigen::MatrixXd fisher_resimulated;  ///< F of the optimal input replayed on CVODES (empty on failure)
  double information_collocation = 0.0;  ///< criterion_information(criterion, F_coll)
  double information_resimulated = 0.0;  ///< the same for the replayed F (NaN on failure)
  std::vector<double> start_information;  ///< information reached from each start (NaN if failed)
  /// The solves of the returned start: one, or two when the fallback ran.
  std::vector<DesignAttempt> attempts;
};

/// The criterion as a quantity to maximise: T → trace F, D → log det F,
/// E → λ_min(F), A → −trace F⁻¹. NaN if F is not positive definite (A, D).
double criterion_information(DesignCriterion criterion, const Eigen::MatrixXd& fisher);

/// Designs the input; never throws on solver failure (see optimization.status).
/// A model without the needed sensitivity states gives invalid_problem.
InputDesignResult design_input(const Model& model, const InputDesignProblem& problem);

/// F for `inputs` at parameters `p` by simulating `model` (which must carry
/// sensitivity states for J) from `t0`. Throws std::runtime_error naming the
/// simulator's status if the simulation fails, std::invalid_argument on bad sizes.
Eigen::MatrixXd fisher_information(const Model& model, const Inputs& inputs,
                                   std::span<const double> p, double t0,
                                   const MeasurementDesign& measurements,
                                   const std::vector<std::size_t>& parameters);

}  // namespace mo::runtime
