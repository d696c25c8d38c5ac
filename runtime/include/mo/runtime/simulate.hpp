// Simulation of a Model with CVODES.
//
//   der(x) = f(x, u(t), p, t),  x(t0) = x0(p),  t ∈ [t0, tN],
//
// integrated by BDF with Newton iterations on the model's Jacobian ∂f/∂x
// (dense), restarted at input breakpoints, time events and zero crossings of
// the event indicators g(t, x, u, p), where the model's event handler runs.
//
// Forward sensitivities S = ∂x/∂p_J for a parameter list J, with
//   der(S) = ∂f/∂x · S + ∂f/∂p_J,  S(t0) = ∂x0/∂p_J,
// come either from the model's own sensitivity states (the compiler appended
// them), or from CVODES' sensitivity module with that right-hand side built
// from the model's Jacobians, or from CVODES' difference quotients.
// Sensitivities are not corrected for jumps at events (state reinit or event
// times that depend on p): across such events they are wrong.
#pragma once

#include "mo/runtime/input.hpp"
#include "mo/runtime/model.hpp"
#include "mo/runtime/result.hpp"

#include <span>
#include <vector>

namespace mo::runtime {

/// The times at which the trajectory is recorded; the first is t0, the last tN.
struct OutputGrid {
  std::vector<double> times;  ///< non-decreasing, at least one

  /// t0, t0 + h, ..., t_end with h = (t_end - t0) / intervals (intervals + 1 times).
  static OutputGrid uniform(double t0, double t_end, std::size_t intervals);
  /// Exactly these times.
  static OutputGrid at(std::vector<double> times) { return OutputGrid{std::move(times)}; }
};

/// How forward sensitivities are computed.
enum class SensitivityMethod {
  none,               ///< no sensitivities
  model_states,       ///< read from the model's sensitivity states (StateVariable::sensitivity)
  cvodes_analytic,    ///< CVODES sensitivity module, RHS from ∂f/∂x·S + ∂f/∂p
  /// CVODES sensitivity module, RHS by CVODES' difference quotients. Their ~sqrt(eps)
  /// noise makes rtol below ~1e-9 unreachable with error_control (too_much_work).
  cvodes_difference,
};

/// Which sensitivities to compute and how.
struct SensitivityOptions {
  SensitivityMethod method = SensitivityMethod::none;  ///< how
  /// Parameter indices J. For model_states an empty list means every parameter
  /// that has sensitivity states; for the CVODES methods it must be non-empty.
  std::vector<std::size_t> parameters;
  bool staggered = true;      ///< CV_STAGGERED corrector (else CV_SIMULTANEOUS)
  bool error_control = true;  ///< include sensitivities in the local error test
};

/// The linear solver of the integrator's Newton iteration.
enum class LinearSolverChoice {
  automatic,  ///< sparse from 100 states with a Jacobian pattern at most a tenth full, else dense
  dense,      ///< dense LU (SUNDIALS' own)
  sparse,     ///< KLU on the pattern of ∂f/∂x and the diagonal (needs use_model_jacobian)
};

/// Integrator settings.
struct SimulationOptions {
  double relative_tolerance = 1e-6;  ///< CVODES rtol
  /// CVODES atol per state is absolute_tolerance · nominal_i.
  double absolute_tolerance = 1e-8;
  double max_step = 0.0;              ///< largest step size; 0 means unbounded
  long max_steps = 100000;            ///< steps allowed between two outputs or stops
  int max_event_iterations = 50;      ///< handler repeats at one event instant
  long max_events = 100000;           ///< events in one simulation (guards Zeno behaviour)
  bool use_model_jacobian = true;     ///< else CVODES' difference-quotient Jacobian (dense)
  LinearSolverChoice linear_solver = LinearSolverChoice::automatic;
  SensitivityOptions sensitivities;   ///< forward sensitivities
};

/// Simulates `model` from grid.times.front() to grid.times.back() with inputs
/// `inputs` and parameters `p`, recording states, outputs (and sensitivities)
/// at every grid time (right limits at events). Never throws on solver
/// failure: the result's status says what went wrong, and holds the trajectory
/// up to that point. Inconsistent sizes or options give invalid_problem.
/// The model's discrete variables are reset by initial_state() and left at
/// their final values.
SimulationResult simulate(Model& model, const Inputs& inputs, std::span<const double> p,
                          const OutputGrid& grid, const SimulationOptions& options = {});

}  // namespace mo::runtime
