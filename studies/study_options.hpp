// Study options: what Optimica cannot say (the task, experiment design and
// estimation data, discretisation and solver settings), written in the study
// file as a vendor annotation that other Modelica tools ignore:
//
//   optimization Design(objective = ..., startTime = 0, finalTime = 5)
//     extends Plant(F(free = true, min = -5, max = 5));
//   ...
//   annotation(__mocompile(task = "design", criterion = "T", parameters = {"m2"},
//                          outputs = {"y_x", "y_phi"}, sigma = {0.01, 0.01},
//                          measurements = 100, n_e = 100, n_cp = 3));
//   end Design;
//
// Every option can be overridden on the command line (`--option n_cp=1`).
// Unknown names and ill-typed values are errors. docs/study-files.md lists
// every option with its default.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "mo/frontend/diagnostics.hpp"
#include "mo/frontend/flat.hpp"

namespace mo::tools {

/// Every study option with its default.
struct StudyOptions {
  std::string task = "optimal_control";  ///< optimal_control | design | estimation | monte_carlo
  // Discretisation and solver (JModelica's names where it has them).
  int n_e = 50;                          ///< collocation elements
  int n_cp = 3;                          ///< collocation points per element
  std::string scheme = "radau";          ///< radau | gauss
  std::vector<double> element_lengths;   ///< relative lengths, n_e of them; empty: uniform
  std::vector<int> blocking_factors;     ///< elements per control value; empty: one per element
  /// Per input, "name=f1,f2,..." (JModelica's blocking_factors as a dict): that
  /// control's blocking factors, over `blocking_factors`.
  std::vector<std::string> input_blocking_factors;
  /// false: a control without blocking factors takes one value per collocation point
  /// (JModelica's default), not one per element (optimal_control only).
  bool piecewise_constant_controls = true;
  std::vector<std::string> du_bounds;    ///< per input, "name=d": |u_{β+1} − u_β| ≤ d
  std::string init_result;               ///< result file (CSV, Dymola text) for initial guesses
  std::string hessian = "automatic";     ///< automatic | exact | limited_memory
  bool init_traj = true;                 ///< states start from a simulation of the initial inputs
  bool nominal_traj = true;              ///< scale states by that simulation's magnitudes
  /// optimal_control: "nlp" keeps the iteration variables of nonlinear blocks as NLP
  /// unknowns at every collocation point (their residuals as equality constraints);
  /// "newton" solves the blocks by Newton inside each model evaluation.
  std::string nonlinear_blocks = "nlp";
  double tol = 1e-8;                     ///< Ipopt tol
  int max_iter = 1000;                   ///< Ipopt max_iter
  double max_cpu_time = 1e6;             ///< Ipopt max_cpu_time, seconds
  double acceptable_tol = 1e-6;          ///< Ipopt acceptable_tol
  int acceptable_iter = 15;              ///< Ipopt acceptable_iter
  double acceptable_obj_change_tol = 1e20;  ///< Ipopt acceptable_obj_change_tol
  std::vector<std::string> ipopt_options;  ///< further Ipopt options, "name=value" each
  // Experiment design and estimation.
  std::string criterion = "T";             ///< design: A | T | D | E
  std::vector<std::string> parameters;     ///< design: parameters of interest
  std::vector<std::string> outputs;        ///< measured outputs (design, estimation)
  std::vector<double> sigma;               ///< noise standard deviation per measured output
  int measurements = 100;                  ///< design: samples at t0 + k (tf - t0)/N, k = 1..N
  std::vector<double> measurement_times;   ///< design: explicit sample times (overrides)
  std::vector<std::string> starts;         ///< design: initial guesses of the first control
  int random_starts = 0;                   ///< design: starts drawn at random besides those (`starts = N`)
  int seed = 1;                            ///< design: seed of the random starts
  double cluster_tol = 1e-4;               ///< design: relative tolerance that makes two optima one
  bool hessian_fallback = true;            ///< design: retry a failed exact-Hessian solve with L-BFGS
  std::vector<std::string> data;           ///< estimation: one measurement CSV per experiment
  std::vector<std::string> inputs;         ///< estimation: per experiment "u=SPEC;v=SPEC"
  double confidence = 0.95;                ///< estimation: confidence level
  int seeds = 100;                         ///< monte_carlo: noise realisations per input
  // Results.
  bool plot = true;                        ///< write PNG plots (gnuplot)
};

/// A command-line override `name=value`; value text as on the command line
/// (numbers, "strings" or bare words, {a, b} lists).
struct OptionOverride {
  std::string name;
  std::string value;
};

/// The options of `opt` (the annotation) with `overrides` applied on top.
/// Errors (unknown option, wrong type) are reported to `diags` (annotation)
/// or returned as text (overrides); `ok` is false after any error.
struct ParsedOptions {
  StudyOptions options;
  std::vector<std::string> errors;  ///< command-line errors, one per line
  bool ok = true;
};
ParsedOptions parse_study_options(const frontend::flat::Optimization& opt,
                                  const std::vector<OptionOverride>& overrides,
                                  frontend::DiagnosticEngine& diags);

/// Names of all options, for messages and docs.
std::vector<std::string> study_option_names();

}  // namespace mo::tools
