// Optimal control of a Model by direct collocation, solved with Ipopt.
//
//   minimise   Σ_m w_m·y_{k_m}(tf) + Σ_l w_l·∫_{t0}^{tf} y_{k_l}(t) dt
//   over       free controls u_c(t) (piecewise constant per element / block)
//              and free parameters p_f
//   subject to der(x) = f(x, u, p, t), x(t0) = x0(p),
//              x_lo ≤ x(t) ≤ x_hi, u_lo ≤ u_c ≤ u_hi, p_lo ≤ p_f ≤ p_hi,
//              lo ≤ y_k(t) ≤ hi on [t0, tf] (path), lo ≤ y_k(t_i) ≤ hi (point),
//              lo ≤ x_i(tf) ≤ hi (final state),
//
// with y = h(x, u, p, t). Objective terms and constraints refer to model
// outputs: the compiler adds one output per expression. Fixed inputs follow
// given signals. Events and discrete variables are ignored by collocation.
#pragma once

#include "mo/runtime/input.hpp"
#include "mo/runtime/model.hpp"
#include "mo/runtime/result.hpp"

#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace mo::runtime {

/// A closed interval lo ≤ v ≤ hi; infinite ends mean unbounded.
struct Bounds {
  double lo = -std::numeric_limits<double>::infinity();  ///< lower bound
  double hi = std::numeric_limits<double>::infinity();   ///< upper bound
};

/// An input that the optimiser chooses: one value per element (or per block).
struct FreeControl {
  std::size_t input = 0;  ///< model input index
  Bounds bounds;          ///< u_lo ≤ u ≤ u_hi
  /// Initial guess signal, sampled at element midpoints; null means the value
  /// in bounds closest to 0.
  std::shared_ptr<const InputSignal> initial_guess;
  /// Elements per control value (JModelica's blocking_factors), summing to n_e;
  /// empty means one value per element.
  std::vector<int> blocking_factors;
  /// One value at every collocation point instead of one per element: an
  /// algebraic variable kept as an NLP unknown (the iteration variable of a
  /// nonlinear block, see symbolic/loop_inputs.hpp). Between the points of an
  /// element the value is the polynomial through them (degree n_cp − 1);
  /// blocking_factors must be empty; the initial guess is sampled at each point.
  bool per_point = false;
  /// |u_{β+1} − u_β| ≤ max_change between consecutive values (blocks, or points of
  /// a per-point control): JModelica's du_bounds. Infinite: no bound.
  double max_change = std::numeric_limits<double>::infinity();
};

/// A parameter that the optimiser chooses.
struct FreeParameter {
  std::size_t parameter = 0;            ///< model parameter index
  Bounds bounds;                        ///< p_lo ≤ p ≤ p_hi
  std::optional<double> initial_guess;  ///< default: the problem's parameter value
};

/// w·y_output(tf) in the objective.
struct MayerTerm {
  std::size_t output = 0;  ///< model output index
  double weight = 1.0;     ///< multiplier
};

/// w·∫ y_output dt in the objective (Gauss/Radau quadrature per element).
struct LagrangeTerm {
  std::size_t output = 0;  ///< model output index
  double weight = 1.0;     ///< multiplier
};

/// lo ≤ y_output(t) ≤ hi, imposed at every collocation point.
struct PathConstraint {
  std::size_t output = 0;  ///< model output index
  Bounds bounds;           ///< allowed range
};

/// lo ≤ y_output(time) ≤ hi at one instant (interpolated within its element).
struct PointConstraint {
  std::size_t output = 0;  ///< model output index
  double time = 0.0;       ///< t0 ≤ time ≤ tf
  Bounds bounds;           ///< allowed range
};

/// lo ≤ x_state(tf) ≤ hi.
struct FinalStateConstraint {
  std::size_t state = 0;  ///< model state index
  Bounds bounds;          ///< allowed range
};

/// The collocation family: Radau IIA (Legendre–Gauss–Radau) or Gauss (Legendre–Gauss).
enum class CollocationScheme { radau, gauss };

/// How the Hessian of the Lagrangian is obtained.
enum class HessianMode {
  automatic,       ///< exact if the model provides its Hessians and the objective allows it
  exact,           ///< exact; invalid_problem if that is impossible
  limited_memory,  ///< Ipopt's L-BFGS approximation
};

/// The time discretisation (JModelica's n_e, n_cp, hs).
struct CollocationOptions {
  int n_e = 50;  ///< number of elements
  int n_cp = 3;  ///< collocation points per element, 1..10
  CollocationScheme scheme = CollocationScheme::radau;  ///< point family
  /// Relative element lengths (n_e positive numbers, normalised to sum 1);
  /// empty means uniform.
  std::vector<double> element_lengths;
  /// JModelica's init_traj: start the states (sensitivity states included) from a
  /// simulation of the initial inputs; false starts them at their start values.
  bool init_traj = true;
  /// JModelica's nominal_traj: scale each state's variables and its collocation
  /// rows by the largest |x| of that simulation (the nominal attribute where that
  /// is below 1% of it); false uses the nominal attribute. Needs init_traj.
  bool nominal_traj = true;
  /// Initial guesses of states by state index (null or missing: none), e.g. from
  /// a result file (JModelica's init_traj given a result): the state's variables
  /// at every node take the signal's value, over the simulation's or start value.
  std::vector<std::shared_ptr<const InputSignal>> state_guesses;
};

/// One Ipopt iteration, as reported to the progress callback.
struct IterationInfo {
  int iteration = 0;       ///< Ipopt iteration counter
  double objective = 0.0;  ///< objective value (unscaled)
  double inf_pr = 0.0;     ///< primal infeasibility
  double inf_du = 0.0;     ///< dual infeasibility
  bool restoration = false;  ///< in the restoration phase
};

/// Called once per iteration; returning false stops the solver (user_stop).
using ProgressCallback = std::function<bool(const IterationInfo&)>;

/// A callback printing `iter objective inf_pr inf_du` as one line per iteration to `out`.
ProgressCallback print_progress(std::ostream& out);

/// Ipopt settings and robustness behaviour.
struct SolverOptions {
  HessianMode hessian = HessianMode::automatic;  ///< exact or limited-memory
  double tolerance = 1e-8;                       ///< Ipopt `tol`
  int max_iterations = 1000;                     ///< Ipopt `max_iter`
  /// Ipopt `acceptable_tol`: after `acceptable_iterations` iterations below it (and
  /// below `acceptable_objective_change`), stop with status acceptable. L-BFGS
  /// problems such as input design crawl near the optimum: 1e-2 with a
  /// relative objective change of 1e-6 suits them.
  double acceptable_tolerance = 1e-6;
  int acceptable_iterations = 15;            ///< Ipopt `acceptable_iter`
  double acceptable_objective_change = 1e20;  ///< Ipopt `acceptable_obj_change_tol` (relative)
  double max_cpu_seconds = 1e6;                  ///< Ipopt `max_cpu_time`
  std::string log_file;   ///< Ipopt's log (print level 5) goes here if non-empty
  int print_level = 0;    ///< Ipopt console print level (0 = silent)
  ProgressCallback progress;  ///< per-iteration callback, may be empty
  bool scale_by_nominal = true;  ///< user scaling 1/nominal for states (else gradient-based)
  /// MUMPS's own scaling of the KKT matrix (Ipopt `mumps_scaling` 77, else 0).
  /// Input design turns it off: on its KKT matrices MUMPS's symmetric
  /// matching-based scaling with Ipopt's pivot tolerance 1e-6 reports a wrong
  /// inertia (docs/design-formulation.md, "Linear algebra").
  bool mumps_scaling = true;
  /// Retry with other linear-solver/scaling options when the step computation,
  /// restoration or memory fails.
  bool retry_on_solver_failure = true;
  /// Extra Ipopt options by name (string, integer or real as written), applied last.
  std::map<std::string, std::string> ipopt_options;
};

/// A dynamic optimisation problem over a Model.
struct OptimalControlProblem {
  double t0 = 0.0;  ///< start time
  double tf = 1.0;  ///< final time (fixed)
  std::vector<FreeControl> controls;  ///< inputs chosen by the optimiser
  /// Signals of the other inputs, by input index; each input must be either here
  /// or in `controls`.
  std::map<std::size_t, std::shared_ptr<const InputSignal>> fixed_inputs;
  std::vector<double> parameters;  ///< all parameter values; empty means the model's defaults
  std::vector<FreeParameter> free_parameters;  ///< parameters chosen by the optimiser
  std::map<std::size_t, Bounds> state_bounds;  ///< overrides of ModelInfo min/max by state index
  std::vector<MayerTerm> mayer;                ///< terms at tf
  std::vector<LagrangeTerm> lagrange;          ///< integral terms
  std::vector<PathConstraint> path_constraints;      ///< over the horizon
  std::vector<PointConstraint> point_constraints;    ///< at instants
  std::vector<FinalStateConstraint> final_state;     ///< at tf
  CollocationOptions collocation;  ///< discretisation
  SolverOptions solver;            ///< Ipopt settings
};

/// How an optimisation ended; every Ipopt return code maps to one of these.
enum class OptimizationStatus {
  success,                ///< converged to tolerance
  acceptable,             ///< converged to Ipopt's acceptable level
  infeasible,             ///< locally infeasible
  iteration_limit,        ///< max_iterations reached
  time_limit,             ///< max_cpu_seconds reached
  evaluation_error,       ///< NaN/Inf in a model evaluation Ipopt could not avoid
  linear_solver_failure,  ///< step computation failed (also after the retries)
  restoration_failure,    ///< restoration phase failed (also after the retries)
  user_stop,              ///< the progress callback returned false
  /// Ipopt stopped short of its tolerance at a feasible point: the search direction
  /// became too small, or restoration failed although the constraints held. The last
  /// iterate is returned; `kkt` says how far from a KKT point it is.
  stalled,
  invalid_problem,        ///< inconsistent problem description; nothing solved
  solver_error,           ///< any other Ipopt failure; see the message
};

/// Lower-case name of a status, e.g. "iteration_limit".
std::string_view to_string(OptimizationStatus status);

/// Size of the transcribed NLP.
struct NlpSize {
  int variables = 0;            ///< n
  int constraints = 0;          ///< m
  int jacobian_nonzeros = 0;    ///< nnz of ∂g/∂v
  int hessian_nonzeros = 0;     ///< nnz of the Lagrangian Hessian's lower triangle (0 for L-BFGS)
};

/// Unscaled KKT residuals of the returned point (max norms; NaN if unknown).
struct KktResiduals {
  double primal_infeasibility = std::numeric_limits<double>::quiet_NaN();  ///< max |g| violation
  double dual_infeasibility = std::numeric_limits<double>::quiet_NaN();    ///< max |∇L|
  double complementarity = std::numeric_limits<double>::quiet_NaN();       ///< max |z·s|
};

/// Wall-clock seconds spent in each phase.
struct OptimizationTimings {
  double nlp_build = 0.0;             ///< transcription and initial-guess simulation
  double solve = 0.0;                 ///< Ipopt, all attempts, including evaluations
  double function_evaluations = 0.0;  ///< inside f, g, their derivatives and the Hessian
  double resimulation = 0.0;          ///< the re-simulation check
};

/// The optimal input replayed on CVODES, compared with the collocation solution.
struct ResimulationCheck {
  bool performed = false;              ///< false if the simulation failed (see message)
  std::string message;                 ///< the simulator's message on failure
  double max_state_difference = 0.0;   ///< max |x_sim − x_coll| over grid and states
  std::string worst_state;             ///< state where that maximum occurs
  double worst_state_time = 0.0;       ///< time where it occurs
  double max_bound_violation = 0.0;    ///< max excess of x_sim over state/final bounds (≥ 0)
  std::string worst_bound;             ///< state whose bound is violated most
  double worst_bound_time = 0.0;       ///< time of that violation
  ResultTable resimulated;             ///< states, then inputs, on the collocation grid
};

/// The outcome of an optimisation; filled with the last iterate on failure.
struct OptimizationResult {
  OptimizationStatus status = OptimizationStatus::solver_error;  ///< how it ended
  std::string message;        ///< what happened, including retries
  std::vector<std::string> retries;  ///< one line per retried solve: what was changed
  double objective = 0.0;     ///< objective at the returned point
  int iterations = 0;         ///< Ipopt iterations of the last attempt
  KktResiduals kkt;           ///< how close the returned point is to a KKT point
  NlpSize size;               ///< NLP dimensions
  OptimizationTimings timings;  ///< where the time went
  /// States then inputs at every element boundary and collocation point (sorted by time).
  ResultTable trajectories;
  std::vector<double> parameters;  ///< all parameter values at the returned point
  std::vector<double> element_times;  ///< t0 = τ_0 < ... < τ_ne = tf
  /// Per FreeControl: the value on each element (n_e values); for a per-point
  /// control the values at the collocation points, element by element (n_e·n_cp).
  std::vector<std::vector<double>> control_values;
  /// The collocation points in [0, 1] of the scheme used (n_cp of them), with
  /// which per-point control values are interpolated.
  std::vector<double> collocation_points;
  ResimulationCheck check;  ///< replay of the optimal input on CVODES

  /// True if status is success or acceptable.
  [[nodiscard]] bool ok() const {
    return status == OptimizationStatus::success || status == OptimizationStatus::acceptable;
  }
};

/// Solves `problem` for `model` (which is cloned, not modified). Never throws on
/// solver failure: the status says what went wrong and the last iterate is
/// returned; an inconsistent problem gives invalid_problem with a message.
OptimizationResult solve(const Model& model, const OptimalControlProblem& problem);

/// The inputs of the optimum as signals: piecewise-constant controls on the
/// element grid, the problem's fixed signals for the rest, in model order.
Inputs optimal_inputs(const OptimalControlProblem& problem, const OptimizationResult& result,
                      std::size_t num_inputs);

/// Writes `trajectories.csv`, `resimulated.csv` and `summary.json` into `directory`
/// (which must exist), each atomically; `info` is the model's (for names).
/// Throws std::system_error on I/O failure.
void write_optimization_result(const std::string& directory, const OptimizationResult& result,
                               const ModelInfo& info);
/// The summary as a JSON document: status, message, retries, objective, iterations,
/// NLP size, timings, parameters and the re-simulation check.
std::string optimization_summary_json(const OptimizationResult& result,
                                      const ModelInfo& info);

}  // namespace mo::runtime
