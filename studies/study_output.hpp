// Study data in and results out: measurement CSVs, experiment inputs, the
// result files (summary.json, trajectories.csv, resimulated.csv,
// designed_input.csv, fit.csv) and gnuplot figures (the paper's Figs 6-9).
#pragma once

#include <nlohmann/json.hpp>

#include <map>
#include <memory>
#include <ostream>
#include <string>

#include "mo/runtime/design.hpp"
#include "mo/runtime/estimate.hpp"
#include "study_options.hpp"

namespace mo::tools {

/// `path` as given if it exists (relative to the working directory), else
/// relative to the directory of `study_file`.
std::string resolve_path(const std::string& study_file, const std::string& path);

/// A measurement CSV: header `time,<output>,...`, empty fields or NaN for
/// missing samples. Columns are matched to model outputs by name (only those
/// listed in options.outputs, if any); σ from options.sigma (one per column,
/// or one for all). Throws UsageError naming file and line on bad data.
runtime::MeasurementTable read_measurements(const std::string& path, const runtime::ModelInfo& info,
                                            const StudyOptions& options);

/// Signals of the inputs that "u=SPEC;v=SPEC" names (see parse_signal; csv:
/// and pwc: files relative to the study file). Throws UsageError for an
/// unknown input, one named twice or a bad SPEC.
std::map<std::size_t, std::shared_ptr<const runtime::InputSignal>> given_inputs(
    const runtime::ModelInfo& info, const std::string& spec, const std::string& study_file);

/// given_inputs(), which must give every model input a signal (else UsageError).
std::map<std::size_t, std::shared_ptr<const runtime::InputSignal>> experiment_inputs(
    const runtime::ModelInfo& info, const std::string& spec, const std::string& study_file);

/// Owning Inputs that refer to the shared signals (input i from m.at(i)).
runtime::Inputs inputs_of(const std::map<std::size_t, std::shared_ptr<const runtime::InputSignal>>& m,
                          std::size_t n);

/// Writes trajectories.csv, resimulated.csv and summary.json (with `extra`
/// merged into the summary), each atomically.
void write_optimization_outputs(const std::string& dir, const runtime::ModelInfo& info,
                                const runtime::OptimalControlProblem& problem,
                                const runtime::OptimizationResult& result,
                                const nlohmann::json& extra);

/// summary.json of a study that ended without a result: `status` "error",
/// `message` saying why, the model's name and `extra` merged in (a
/// multistart's table of starts); the folder is created if missing.
void write_error_summary(const std::string& dir, const runtime::ModelInfo& info, const std::string& message,
                         const nlohmann::json& extra);

/// The design-specific part of summary.json: criterion, parameters, Fisher
/// matrices (collocation and re-simulated), information per start.
nlohmann::json design_json(const runtime::ModelInfo& info, const runtime::InputDesignProblem& d,
                           const runtime::InputDesignResult& r);

/// designed_input.csv: `time,<control>...`, one row per control interval
/// start and one at tf; read it back with `u=pwc:designed_input.csv`.
void write_designed_input(const std::string& dir, const runtime::ModelInfo& info,
                          const runtime::OptimalControlProblem& problem,
                          const runtime::OptimizationResult& result);

/// summary.json (estimates, CIs, covariance, correlation, warnings) and
/// fit.csv (outputs simulated at the estimate on the data times, per experiment).
void write_estimation_outputs(const std::string& dir, runtime::Model& model,
                              const runtime::EstimationProblem& e,
                              const runtime::EstimationResult& r);

/// Prints the estimates with their confidence intervals and warnings.
void print_estimates(std::ostream& os, const runtime::EstimationResult& r);

}  // namespace mo::tools
