// The results of a simulation.
//
//   trajectory  (t_k, x(t_k), y(t_k)),  k = 0..N-1, on the output grid;
//   sensitivities S_x(t_k) = ∂x/∂p_J (nx × |J|) and S_y(t_k) = ∂y/∂p_J
//   = ∂h/∂x·S_x + ∂h/∂p_J for a chosen parameter list J;
//   solver status, statistics and timings.
//
// Files are written atomically: a temporary file in the target's directory is
// written, fsync'ed and renamed over the target, so a reader sees either the
// old file or the complete new one, never a partial file.
#pragma once

#include "mo/runtime/model.hpp"

#include <Eigen/Dense>

#include <functional>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mo::runtime {

/// A table of samples: one time column and named value columns, row by row.
class ResultTable {
public:
  /// A table without columns or rows.
  ResultTable() = default;
  /// An empty table with the given value column names (time is implicit).
  explicit ResultTable(std::vector<std::string> names) : names_(std::move(names)) {}
  /// Appends the row (t, values); values.size() must equal names().size().
  /// Throws std::invalid_argument otherwise.
  void add_row(double t, std::span<const double> values);
  /// Value column names, without time.
  [[nodiscard]] const std::vector<std::string>& names() const { return names_; }
  /// Sample times, one per row.
  [[nodiscard]] const std::vector<double>& times() const { return times_; }
  /// Number of rows.
  [[nodiscard]] std::size_t rows() const { return times_.size(); }
  /// The values of row `k` (no bounds check beyond the span).
  [[nodiscard]] std::span<const double> row(std::size_t k) const;
  /// Value at row k, column j.
  [[nodiscard]] double at(std::size_t k, std::size_t j) const {
    return values_[k * names_.size() + j];
  }
  /// The whole column named `name`; throws std::out_of_range if there is none.
  [[nodiscard]] std::vector<double> column(std::string_view name) const;

private:
  std::vector<std::string> names_;
  std::vector<double> times_;
  std::vector<double> values_;  // row-major, rows() × names_.size()
};

/// How a simulation ended. Every SUNDIALS failure maps to one of these.
enum class SimulationStatus {
  success,                  ///< reached the final output time
  terminated_by_model,      ///< the model called terminate() in an event
  invalid_problem,          ///< sizes, grid or options inconsistent; nothing simulated
  too_much_work,            ///< more than max_steps steps between two stops
  too_much_accuracy,        ///< tolerances cannot be met in floating point
  error_test_failure,       ///< local error test failed repeatedly (or at h_min)
  convergence_failure,      ///< Newton iteration failed repeatedly (or at h_min)
  linear_solver_failure,    ///< Jacobian factorisation or solve failed
  rhs_failure,              ///< f returned non-finite values the solver could not avoid
  event_indicator_failure,  ///< g returned non-finite values
  event_iteration_limit,    ///< the event handler kept changing discrete variables
  event_limit,              ///< more than max_events events (e.g. Zeno behaviour)
  solver_error,             ///< any other SUNDIALS error; see the message
};

/// Lower-case name of a status, e.g. "too_much_work".
std::string_view to_string(SimulationStatus status);

/// Counters and timings of one simulation.
struct SolverStatistics {
  long steps = 0;                    ///< integrator steps, summed over restarts
  long rhs_evaluations = 0;          ///< f evaluations (excluding finite-difference Jacobians)
  long jacobian_evaluations = 0;     ///< Jacobian evaluations by the linear solver
  long sensitivity_rhs_evaluations = 0;  ///< sensitivity right-hand side evaluations
  long error_test_failures = 0;      ///< rejected steps
  long nonlinear_convergence_failures = 0;  ///< Newton failures
  long events = 0;                   ///< handled state and time events
  long restarts = 0;                 ///< integrator re-initialisations (events and input breakpoints)
  long difference_jacobians = 0;     ///< Jacobians taken by differences: the model's was not finite there
  bool sparse_linear_solver = false;  ///< KLU (SimulationOptions::linear_solver), else dense LU
  double wall_time_seconds = 0.0;    ///< whole simulate() call
};

/// A point where the model's right-hand side gave a value that is not finite.
struct NonFinitePoint {
  double t = 0.0;
  std::vector<double> x, u;  ///< states and inputs there
};

/// The outcome of simulate().
struct SimulationResult {
  SimulationStatus status = SimulationStatus::success;  ///< how it ended
  std::string message;         ///< empty on success; otherwise what failed, at which time
  ResultTable trajectory;      ///< columns: states, then outputs, by their names
  std::vector<double> event_times;  ///< times of handled events, ascending
  SolverStatistics statistics;      ///< counters and timings
  std::vector<std::size_t> sensitivity_parameters;  ///< parameter indices J, if any
  /// S_x(t_k), one matrix per trajectory row (rows: states, cols: J); empty without sensitivities.
  std::vector<Eigen::MatrixXd> state_sensitivities;
  /// S_y(t_k), one matrix per trajectory row (rows: outputs, cols: J).
  std::vector<Eigen::MatrixXd> output_sensitivities;
  /// The last point where the right-hand side was not finite, if any: a step
  /// CVODES tried and rejected (it then retries with a smaller one). When the
  /// run fails, the likely cause; the caller can name its equation.
  std::optional<NonFinitePoint> non_finite_rhs;
  /// What the model's solvers report about the run (Model::notes()): e.g. a
  /// singular linear block solved by its minimum-norm solution.
  std::vector<std::string> warnings;

  /// True if status is success or terminated_by_model.
  [[nodiscard]] bool ok() const {
    return status == SimulationStatus::success ||
           status == SimulationStatus::terminated_by_model;
  }
};

/// The sensitivities of `result` as a table over its times, columns
/// `d(<state>)/d(<parameter>)` then `d(<output>)/d(<parameter>)`, names from
/// `info` (the model simulated). Empty (no columns, no rows) without sensitivities.
ResultTable sensitivity_table(const SimulationResult& result, const ModelInfo& info);

/// Writes the bytes that `write` produces to `path` atomically (temporary file
/// in the same directory, fsync, rename, fsync of the directory). If `write`
/// throws or any system call fails, the temporary file is removed, the target
/// is left as it was, and std::system_error (or the writer's exception) is thrown.
void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& write);
/// Writes `table` as CSV (`time,<names>` header, round-trip precision) atomically.
void write_csv_atomic(const std::string& path, const ResultTable& table);
/// A JSON object with status, message, statistics, event times and the
/// trajectory's column names, pretty-printed.
std::string summary_json(const SimulationResult& result);
/// Writes summary_json(result) to `path` atomically.
void write_summary_json(const std::string& path, const SimulationResult& result);

}  // namespace mo::runtime
