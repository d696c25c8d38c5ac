// Input signals and CSV input tables.
#include "mo/runtime/input.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

namespace mo::runtime {

double InputSignal::derivative_before(double t) const {
  const double h = 1e-7 * std::max(1.0, std::abs(t));
  return (value_before(t) - value(t - h)) / h;
}

namespace {

class ConstantSignal final : public InputSignal {
public:
  explicit ConstantSignal(double v) : value_(v) {}
  double value(double) const override { return value_; }
  double derivative_before(double) const override { return 0.0; }

private:
  double value_;
};

class SineSignal final : public InputSignal {
public:
  SineSignal(double amplitude, double freq_hz, double phase, double offset)
      : amplitude_(amplitude), omega_(2.0 * std::numbers::pi * freq_hz), phase_(phase),
        offset_(offset) {}
  double value(double t) const override {
    return offset_ + amplitude_ * std::sin(omega_ * t + phase_);
  }
  double derivative_before(double t) const override {
    return amplitude_ * omega_ * std::cos(omega_ * t + phase_);
  }

private:
  double amplitude_, omega_, phase_, offset_;
};

class StepSignal final : public InputSignal {
public:
  StepSignal(double height, double start, double offset)
      : height_(height), start_(start), offset_(offset) {}
  double value(double t) const override { return t < start_ ? offset_ : offset_ + height_; }
  double value_before(double t) const override {
    return t <= start_ ? offset_ : offset_ + height_;
  }
  double derivative_before(double) const override { return 0.0; }
  std::vector<double> breakpoints(double t0, double t1) const override {
    if (start_ > t0 && start_ < t1) return {start_};
    return {};
  }

private:
  double height_, start_, offset_;
};

class PiecewiseConstantSignal final : public InputSignal {
public:
  PiecewiseConstantSignal(std::vector<double> times, std::vector<double> values)
      : times_(std::move(times)), values_(std::move(values)) {}
  double value(double t) const override {
    auto i = std::upper_bound(times_.begin(), times_.end(), t) - times_.begin();
    return values_[i == 0 ? 0 : static_cast<std::size_t>(i - 1)];
  }
  double value_before(double t) const override {
    auto i = std::lower_bound(times_.begin(), times_.end(), t) - times_.begin();
    return values_[i == 0 ? 0 : static_cast<std::size_t>(i - 1)];
  }
  double derivative_before(double) const override { return 0.0; }
  std::vector<double> breakpoints(double t0, double t1) const override {
    std::vector<double> out;
    for (std::size_t k = 1; k < times_.size(); ++k)  // times_[0] changes nothing
      if (times_[k] > t0 && times_[k] < t1) out.push_back(times_[k]);
    return out;
  }

private:
  std::vector<double> times_, values_;
};

class PulseSignal final : public InputSignal {
public:
  PulseSignal(double amplitude, double period, double width, double start, double offset)
      : amplitude_(amplitude), period_(period), width_(width), start_(start), offset_(offset) {}
  double value(double t) const override { return at(t, false); }
  double value_before(double t) const override { return at(t, true); }
  double derivative_before(double) const override { return 0.0; }
  std::vector<double> breakpoints(double t0, double t1) const override {
    std::vector<double> out;
    double k0 = std::max(0.0, std::floor((t0 - start_) / period_));
    for (double k = k0;; k += 1.0) {
      double rise = start_ + k * period_;
      if (rise >= t1) break;
      if (rise > t0) out.push_back(rise);
      double fall = rise + width_;
      if (fall > t0 && fall < t1 && width_ < period_) out.push_back(fall);
    }
    return out;
  }

private:
  // Left limits: the pulse is "on" on (rise, fall] instead of [rise, fall).
  double at(double t, bool left) const {
    if (left ? t <= start_ : t < start_) return offset_;
    double phase = std::fmod(t - start_, period_);
    bool on = left ? (phase > 0.0 && phase <= width_) || (phase == 0.0 && width_ == period_)
                   : phase < width_;
    return on ? offset_ + amplitude_ : offset_;
  }
  double amplitude_, period_, width_, start_, offset_;
};

class TableColumnSignal final : public InputSignal {
public:
  TableColumnSignal(std::shared_ptr<const InputTable> table, std::size_t column)
      : table_(std::move(table)), column_(column) {}
  double value(double t) const override {
    const auto& ts = table_->times;
    auto i = static_cast<std::size_t>(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin());
    return interpolate(i, t);
  }
  double value_before(double t) const override {
    const auto& ts = table_->times;
    auto i = static_cast<std::size_t>(std::lower_bound(ts.begin(), ts.end(), t) - ts.begin());
    return interpolate(i, t);
  }
  // The slope of the segment that ends at or after t (0 where held).
  double derivative_before(double t) const override {
    const auto& ts = table_->times;
    auto i = static_cast<std::size_t>(std::lower_bound(ts.begin(), ts.end(), t) - ts.begin());
    if (i == 0 || i == ts.size()) return 0.0;
    const auto& ys = table_->columns[column_];
    return (ys[i] - ys[i - 1]) / (ts[i] - ts[i - 1]);
  }
  // Every sample time is a kink (or a jump) of the linear interpolant.
  std::vector<double> breakpoints(double t0, double t1) const override {
    std::vector<double> out;
    for (double t : table_->times)
      if (t > t0 && t < t1 && (out.empty() || out.back() != t)) out.push_back(t);
    return out;
  }

private:
  // Interpolates on [times[i-1], times[i]], holding the end values outside.
  double interpolate(std::size_t i, double t) const {
    const auto& ts = table_->times;
    const auto& ys = table_->columns[column_];
    if (i == 0) return ys.front();
    if (i == ts.size()) return ys.back();
    double w = (t - ts[i - 1]) / (ts[i] - ts[i - 1]);
    return ys[i - 1] + w * (ys[i] - ys[i - 1]);
  }
  std::shared_ptr<const InputTable> table_;
  std::size_t column_;
};

std::string_view trim(std::string_view s) {
  auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t begin = 0;
  for (;;) {
    std::size_t comma = line.find(',', begin);
    fields.push_back(trim(line.substr(begin, comma - begin)));
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  return fields;
}

// The header's names; RFC 4180 quoting ("a[1,2]", "" for a quote), as
// write_csv_atomic writes a name with a comma or a quote.
std::vector<std::string> split_header(std::string_view line) {
  std::vector<std::string> fields;
  std::size_t i = 0;
  for (;;) {
    while (i < line.size() && line[i] == ' ') ++i;
    std::string field;
    if (i < line.size() && line[i] == '"') {
      for (++i; i < line.size(); ++i) {
        if (line[i] != '"') {
          field += line[i];
        } else if (i + 1 < line.size() && line[i + 1] == '"') {
          field += '"';
          ++i;
        } else {
          ++i;
          break;
        }
      }
      const std::size_t comma = line.find(',', i);
      fields.push_back(std::move(field));
      if (comma == std::string_view::npos) break;
      i = comma + 1;
      continue;
    }
    const std::size_t comma = line.find(',', i);
    fields.emplace_back(trim(line.substr(i, comma - i)));
    if (comma == std::string_view::npos) break;
    i = comma + 1;
  }
  return fields;
}

[[noreturn]] void fail(const std::string& source, std::size_t line, const std::string& what) {
  throw InputFileError(source + ":" + std::to_string(line) + ": error: " + what);
}

}  // namespace

namespace {

class SharedSignal final : public InputSignal {
public:
  explicit SharedSignal(std::shared_ptr<const InputSignal> signal) : signal_(std::move(signal)) {}
  [[nodiscard]] double value(double t) const override { return signal_->value(t); }
  [[nodiscard]] double value_before(double t) const override { return signal_->value_before(t); }
  [[nodiscard]] double derivative_before(double t) const override {
    return signal_->derivative_before(t);
  }
  [[nodiscard]] std::vector<double> breakpoints(double t0, double t1) const override {
    return signal_->breakpoints(t0, t1);
  }

private:
  std::shared_ptr<const InputSignal> signal_;
};

}  // namespace

std::unique_ptr<InputSignal> shared_input(std::shared_ptr<const InputSignal> signal) {
  return std::make_unique<SharedSignal>(std::move(signal));
}

std::unique_ptr<InputSignal> constant_input(double value) {
  return std::make_unique<ConstantSignal>(value);
}

std::unique_ptr<InputSignal> sine_input(double amplitude, double freq_hz, double phase,
                                        double offset) {
  return std::make_unique<SineSignal>(amplitude, freq_hz, phase, offset);
}

std::unique_ptr<InputSignal> step_input(double height, double start_time, double offset) {
  return std::make_unique<StepSignal>(height, start_time, offset);
}

std::unique_ptr<InputSignal> pulse_input(double amplitude, double period, double width,
                                         double start_time, double offset) {
  if (!(width > 0.0 && width <= period))
    throw std::invalid_argument("pulse_input: need 0 < width <= period, got width " +
                                std::to_string(width) + ", period " + std::to_string(period));
  return std::make_unique<PulseSignal>(amplitude, period, width, start_time, offset);
}

std::unique_ptr<InputSignal> piecewise_constant_input(std::vector<double> times,
                                                      std::vector<double> values) {
  if (times.empty() || times.size() != values.size())
    throw std::invalid_argument("piecewise_constant_input: need as many values as times (" +
                                std::to_string(times.size()) + " times, " +
                                std::to_string(values.size()) + " values), at least one");
  for (std::size_t k = 1; k < times.size(); ++k)
    if (!(times[k] > times[k - 1]))
      throw std::invalid_argument("piecewise_constant_input: times must strictly ascend (" +
                                  std::to_string(times[k - 1]) + " then " +
                                  std::to_string(times[k]) + ")");
  return std::make_unique<PiecewiseConstantSignal>(std::move(times), std::move(values));
}

std::vector<double> lagrange_weights(const std::vector<double>& points, double tau) {
  std::vector<double> w(points.size(), 1.0);
  for (std::size_t j = 0; j < points.size(); ++j)
    for (std::size_t m = 0; m < points.size(); ++m)
      if (m != j) w[j] *= (tau - points[m]) / (points[j] - points[m]);
  return w;
}

namespace {

class CollocatedSignal final : public InputSignal {
public:
  CollocatedSignal(std::vector<double> starts, double end, std::vector<double> points,
                   std::vector<double> values)
      : starts_(std::move(starts)), end_(end), points_(std::move(points)), values_(std::move(values)) {}
  double value(double t) const override { return at(t, false); }
  double value_before(double t) const override { return at(t, true); }
  std::vector<double> breakpoints(double t0, double t1) const override {
    std::vector<double> out;
    for (std::size_t i = 1; i < starts_.size(); ++i)
      if (starts_[i] > t0 && starts_[i] < t1) out.push_back(starts_[i]);
    return out;
  }

private:
  double at(double t, bool left) const {
    auto it = left ? std::lower_bound(starts_.begin(), starts_.end(), t)
                   : std::upper_bound(starts_.begin(), starts_.end(), t);
    const std::size_t i = it == starts_.begin() ? 0 : std::size_t(it - starts_.begin()) - 1;
    const double next = i + 1 < starts_.size() ? starts_[i + 1] : end_;
    const double tau = (t - starts_[i]) / (next - starts_[i]);
    const std::vector<double> w = lagrange_weights(points_, tau);
    double sum = 0.0;
    for (std::size_t j = 0; j < w.size(); ++j) sum += w[j] * values_[i * points_.size() + j];
    return sum;
  }
  std::vector<double> starts_;
  double end_;
  std::vector<double> points_, values_;
};

}  // namespace

std::unique_ptr<InputSignal> collocated_input(std::vector<double> starts, double end,
                                              std::vector<double> points, std::vector<double> values) {
  if (starts.empty() || points.empty() || values.size() != starts.size() * points.size())
    throw std::invalid_argument("collocated_input: need points.size() values per element");
  for (std::size_t k = 1; k < starts.size(); ++k)
    if (!(starts[k] > starts[k - 1])) throw std::invalid_argument("collocated_input: element starts must ascend");
  if (!(end > starts.back())) throw std::invalid_argument("collocated_input: end must follow the last start");
  return std::make_unique<CollocatedSignal>(std::move(starts), end, std::move(points), std::move(values));
}

InputTable parse_input_csv(std::string_view text, const std::string& source) {
  InputTable table;
  bool have_header = false;
  std::size_t line_no = 0;
  std::size_t header_line = 0;
  while (!text.empty()) {
    std::size_t eol = text.find('\n');
    std::string_view line = trim(text.substr(0, eol));
    text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
    ++line_no;
    if (line.empty() || line.front() == '#') continue;
    if (!have_header) {
      const std::vector<std::string> fields = split_header(line);
      if (fields.size() < 2 || fields[0] != "time")
        fail(source, line_no, "header must be 'time,<input>,...' with at least one input column");
      for (std::size_t j = 1; j < fields.size(); ++j) {
        if (fields[j].empty()) fail(source, line_no, "empty name of column " + std::to_string(j + 1));
        std::string name(fields[j]);
        if (std::find(table.names.begin(), table.names.end(), name) != table.names.end())
          fail(source, line_no, "duplicate column '" + name + "'");
        table.names.push_back(std::move(name));
      }
      table.columns.resize(table.names.size());
      have_header = true;
      header_line = line_no;
      continue;
    }
    auto fields = split_fields(line);
    if (fields.size() != table.names.size() + 1)
      fail(source, line_no, "expected " + std::to_string(table.names.size() + 1) +
                                " fields, found " + std::to_string(fields.size()));
    for (std::size_t j = 0; j < fields.size(); ++j) {
      double v = 0.0;
      auto f = fields[j];
      auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
      if (f.empty() || ec != std::errc() || ptr != f.data() + f.size())
        fail(source, line_no, "field " + std::to_string(j + 1) + " ('" + std::string(f) +
                                  "') is not a number");
      if (!std::isfinite(v))
        fail(source, line_no, "field " + std::to_string(j + 1) + " is not finite");
      if (j == 0) {
        const auto& ts = table.times;
        if (!ts.empty() && v < ts.back())
          fail(source, line_no, "time " + std::string(f) + " is less than the previous time");
        if (ts.size() >= 2 && v == ts.back() && v == ts[ts.size() - 2])
          fail(source, line_no, "time " + std::string(f) + " appears more than twice");
        table.times.push_back(v);
      } else {
        table.columns[j - 1].push_back(v);
      }
    }
  }
  if (!have_header) fail(source, line_no == 0 ? 1 : line_no, "no header line 'time,<input>,...'");
  if (table.times.empty()) fail(source, header_line, "no data rows after the header");
  return table;
}

InputTable read_input_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputFileError(path + ":1: error: cannot open file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return parse_input_csv(buffer.str(), path);
}

std::unique_ptr<InputSignal> table_input(std::shared_ptr<const InputTable> table,
                                         std::size_t column) {
  if (column >= table->columns.size())
    throw std::out_of_range("table_input: column " + std::to_string(column) + " of " +
                            std::to_string(table->columns.size()));
  return std::make_unique<TableColumnSignal>(std::move(table), column);
}

std::unique_ptr<InputSignal> table_input(std::shared_ptr<const InputTable> table,
                                         const std::string& name) {
  auto it = std::find(table->names.begin(), table->names.end(), name);
  if (it == table->names.end())
    throw std::out_of_range("table_input: no column named '" + name + "'");
  auto column = static_cast<std::size_t>(it - table->names.begin());
  return std::make_unique<TableColumnSignal>(std::move(table), column);
}

Inputs::Inputs(std::vector<std::unique_ptr<InputSignal>> signals)
    : signals_(std::move(signals)) {}

void Inputs::add(std::unique_ptr<InputSignal> signal) { signals_.push_back(std::move(signal)); }

void Inputs::evaluate(double t, std::span<double> u) const {
  for (std::size_t i = 0; i < signals_.size(); ++i) u[i] = signals_[i]->value(t);
}

void Inputs::evaluate_before(double t, std::span<double> u) const {
  for (std::size_t i = 0; i < signals_.size(); ++i) u[i] = signals_[i]->value_before(t);
}

void Inputs::derivative_before(double t, std::span<double> udot) const {
  for (std::size_t i = 0; i < signals_.size(); ++i) udot[i] = signals_[i]->derivative_before(t);
}

std::vector<double> Inputs::breakpoints(double t0, double t1) const {
  std::vector<double> all;
  for (const auto& s : signals_) {
    auto b = s->breakpoints(t0, t1);
    all.insert(all.end(), b.begin(), b.end());
  }
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  return all;
}

}  // namespace mo::runtime
