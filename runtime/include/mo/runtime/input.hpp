// Input signals u(t) that drive a simulation.
//
//   u_i(t) = s_i(t),  i = 1..nu,
//
// each s_i piecewise smooth. A signal lists its breakpoints — times where it
// or its first derivative jumps — so the integrator stops and restarts there
// instead of stepping over a discontinuity. At a jump, value(t) is the
// right-hand limit; the simulator evaluates left of it with value_before(t).
#pragma once

#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace mo::runtime {

/// One scalar input signal s(t).
class InputSignal {
public:
  /// Signals are owned through InputSignal pointers.
  virtual ~InputSignal() = default;
  /// s(t), right-continuous at jumps.
  [[nodiscard]] virtual double value(double t) const = 0;
  /// lim s(τ) for τ ↑ t: differs from value(t) only at a jump.
  [[nodiscard]] virtual double value_before(double t) const { return value(t); }
  /// ṡ just before t (the left derivative): how an input moves with an event
  /// time that moves (the g_u u̇ term of dτ/dp). The default is the one-sided
  /// difference (value_before(t) − value(t − h))/h, h = 1e-7·max(1, |t|).
  [[nodiscard]] virtual double derivative_before(double t) const;
  /// Breakpoints in the open interval (t0, t1), ascending, without duplicates.
  [[nodiscard]] virtual std::vector<double> breakpoints(double t0, double t1) const {
    (void)t0, (void)t1;
    return {};
  }
};

/// s(t) = value.
std::unique_ptr<InputSignal> constant_input(double value);
/// s(t) = offset + amplitude·sin(2π·freq_hz·t + phase); smooth, no breakpoints.
std::unique_ptr<InputSignal> sine_input(double amplitude, double freq_hz, double phase = 0.0,
                                        double offset = 0.0);
/// s(t) = offset for t < start_time, offset + height from start_time on.
std::unique_ptr<InputSignal> step_input(double height, double start_time, double offset = 0.0);
/// Periodic pulse: offset + amplitude during [start + k·period, start + k·period + width),
/// offset otherwise (before start too). Throws std::invalid_argument unless
/// 0 < width ≤ period.
std::unique_ptr<InputSignal> pulse_input(double amplitude, double period, double width,
                                         double start_time = 0.0, double offset = 0.0);
/// A signal that forwards to `signal`, so one signal can drive several Inputs.
std::unique_ptr<InputSignal> shared_input(std::shared_ptr<const InputSignal> signal);
/// Piecewise constant: values[k] on [times[k], times[k+1]), values[0] before
/// times[0], values.back() after. Throws std::invalid_argument unless sizes are
/// equal and non-zero and times strictly ascend.
std::unique_ptr<InputSignal> piecewise_constant_input(std::vector<double> times,
                                                      std::vector<double> values);
/// Piecewise polynomial: on element i ([starts[i], starts[i+1]), the last one
/// unbounded), the polynomial in τ = (t − starts[i])/length_i through the values
/// values[i·K + j] at τ = points[j] (K = points.size(); length_i of the last
/// element is `end − starts.back()`). A per-point control of a collocation
/// result. Throws std::invalid_argument on inconsistent sizes or times.
std::unique_ptr<InputSignal> collocated_input(std::vector<double> starts, double end,
                                              std::vector<double> points, std::vector<double> values);
/// ℓ_j(τ), j = 0..K−1: the Lagrange basis over `points` at τ (1 for K = 1).
std::vector<double> lagrange_weights(const std::vector<double>& points, double tau);

/// A table of sampled inputs: one time column and named value columns.
/// Linear interpolation between rows, held constant before the first and after
/// the last row. Two rows with equal time make a jump (left value, then right).
struct InputTable {
  std::vector<std::string> names;            ///< value column names (header, without time)
  std::vector<double> times;                 ///< non-decreasing, no time thrice
  std::vector<std::vector<double>> columns;  ///< columns[j][k] = value j at times[k]
};

/// A CSV input file that could not be read; what() is `file.csv:line: error: ...`.
class InputFileError : public std::runtime_error {
public:
  /// Takes the complete message, `file.csv:line: error: ...`.
  using std::runtime_error::runtime_error;
};

/// Reads a CSV input table: header `time,<name>,...`, then numeric rows; blank
/// lines and lines starting with '#' are skipped. Throws InputFileError naming
/// file and line on: unreadable file, missing header, wrong field count,
/// non-numeric or non-finite field, decreasing time, or fewer than one row.
InputTable read_input_csv(const std::string& path);
/// Same as read_input_csv on text already in memory; `source_name` is used in messages.
InputTable parse_input_csv(std::string_view text, const std::string& source_name);

/// A simulation or optimisation result read as a table of signals, for initial
/// guesses, measurements and input signals: a CSV file (as read_input_csv:
/// mocompile's result.csv or trajectories.csv), Dymola's textual result format
/// (first line `#1`, then the matrices Aclass, name, description, dataInfo,
/// data_1 and data_2 as text; Dymola's and JModelica's `.txt` results), or a
/// MATLAB .mat file (see is_mat_file in mat_file.hpp). In Dymola's layout every
/// variable becomes a column, those of data_1 (parameters) constant, negated
/// aliases (a negative dataInfo column) negated. A time that repeats more than
/// twice keeps its first and last rows. Throws InputFileError naming the file
/// on anything else or on a malformed matrix.
InputTable read_result_table(const std::string& path);

/// The signal of column `column` of `table` (shared, not copied).
/// Throws std::out_of_range if the column does not exist.
std::unique_ptr<InputSignal> table_input(std::shared_ptr<const InputTable> table,
                                         std::size_t column);
/// The signal of the column named `name`; throws std::out_of_range if absent.
std::unique_ptr<InputSignal> table_input(std::shared_ptr<const InputTable> table,
                                         const std::string& name);

/// The inputs of a model: one signal per model input, in the model's order.
class Inputs {
public:
  /// No signals: for models without inputs.
  Inputs() = default;
  /// Takes ownership of one signal per input.
  explicit Inputs(std::vector<std::unique_ptr<InputSignal>> signals);
  /// Appends the signal of the next input.
  void add(std::unique_ptr<InputSignal> signal);
  /// Number of signals (must equal the model's nu when simulating).
  [[nodiscard]] std::size_t size() const { return signals_.size(); }
  /// u = (s_1(t), ..., s_nu(t)); right limits at jumps.
  void evaluate(double t, std::span<double> u) const;
  /// u just before t (left limits), for the end of an integration segment.
  void evaluate_before(double t, std::span<double> u) const;
  /// u̇ just before t (InputSignal::derivative_before).
  void derivative_before(double t, std::span<double> udot) const;
  /// Union of all signals' breakpoints in (t0, t1), ascending, without duplicates.
  [[nodiscard]] std::vector<double> breakpoints(double t0, double t1) const;

private:
  std::vector<std::unique_ptr<InputSignal>> signals_;
};

}  // namespace mo::runtime
