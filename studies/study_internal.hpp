// Internals shared by the study tasks (study.cpp, study_monte_carlo.cpp).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "common.hpp"
#include "mo/symbolic/loop_inputs.hpp"
#include "mo/runtime/design.hpp"
#include "mo/runtime/estimate.hpp"
#include "study.hpp"
#include "study_options.hpp"
#include "study_problem.hpp"

namespace mo::tools::detail {

/// Everything a task needs.
struct Study {
  frontend::flat::Model& flat;
  const StudyCli& cli;
  StudyOptions opt;
  ProblemOutputs problem;
  BuiltModel built;
  /// Iteration variables of nonlinear blocks turned into inputs (nonlinear_blocks = "nlp").
  symbolic::LoopExposure loops{};
  /// With loops: the model as lowered, Newton inside, with the iteration variables
  /// as outputs, for the initial guess of those variables (null without loops).
  std::unique_ptr<BuiltModel> newton{};
  /// Estimates for monte_carlo; empty: runtime::estimate_parameters on `built` (a model with events sets it).
  std::function<runtime::EstimationResult(const runtime::EstimationProblem&)> estimate{};
  [[nodiscard]] const runtime::ModelInfo& info() const { return built.model->info(); }
};

/// Per-input blocking factors and du_bounds of the options on `p`'s controls;
/// UsageError for an input that is not a control or a malformed entry.
void apply_control_options(const Study& s, runtime::OptimalControlProblem& p);
/// Initial guesses from the option init_result (states by name, controls by
/// input name, iteration variables by their variable's name); returns how many
/// columns were used. UsageError if the file cannot be read or matches nothing.
std::size_t apply_init_result(const Study& s, runtime::OptimalControlProblem& p);
/// With init_traj and s.newton: the iteration variables' initial guesses from a
/// simulation of the model with Newton under the controls' initial guesses, so
/// that the NLP's own initial-guess simulation (which takes them as given
/// signals) follows the model. A failed simulation leaves the start values, with
/// a note on stderr.
void guess_iteration_variables(const Study& s, runtime::OptimalControlProblem& p);

/// Index of output `name`; UsageError listing the outputs otherwise.
std::size_t output_index(const runtime::ModelInfo& info, const std::string& name);
/// Index of parameter `name`; UsageError otherwise.
std::size_t parameter_index(const runtime::ModelInfo& info, const std::string& name);
/// The model's defaults with --set p=v applied.
std::vector<double> parameter_values(const runtime::ModelInfo& info, const StudyCli& cli);
/// Ipopt settings from the options (log to DIR/ipopt.log, progress to the run's status line).
runtime::SolverOptions solver_options(const Study& s);
/// A solver callback showing iteration, objective and infeasibility on the
/// run's status line; empty without a run.
runtime::ProgressCallback solver_progress(RunContext* run);
/// Moves `seconds` (a re-simulation inside a solve) from the solve phase to simulate.
void move_to_simulate(RunContext* run, double seconds);
/// n_e, n_cp, scheme and element lengths.
runtime::CollocationOptions collocation_options(const StudyOptions& o);
/// Parameters declared free = true, with bounds and initial guesses.
std::vector<runtime::FreeParameter> free_parameters(const Study& s);
/// Measured outputs, σ and sample times on [t0, tf] from the options.
runtime::MeasurementDesign measurements(const Study& s, double t0, double tf);
/// The Optimica problem of the study: every input a control (bounds,
/// initialGuess), free parameters, objective terms and constraints through
/// their outputs, collocation and solver options.
runtime::OptimalControlProblem base_problem(const Study& s);
/// Monte-Carlo check of the estimator (task = "monte_carlo").
int monte_carlo(Study& s);

}  // namespace mo::tools::detail
