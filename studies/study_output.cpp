// Study data in, results and figures out; see study_output.hpp.
#include "study_output.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common.hpp"
#include "mo/runtime/input.hpp"
#include "mo/runtime/mat_file.hpp"
#include "mo/runtime/result.hpp"
#include "mo/runtime/simulate.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace mo::tools {

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string part; std::getline(in, part, sep);) out.push_back(part);
  return out;
}

json matrix_json(const Eigen::MatrixXd& m) {
  json rows = json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    json row = json::array();
    for (Eigen::Index j = 0; j < m.cols(); ++j) row.push_back(m(i, j));
    rows.push_back(row);
  }
  return rows;
}

/// Finite numbers as they are, others as null (JSON has no NaN).
json number_json(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

void write_json(const std::string& path, const json& j) {
  runtime::write_file_atomic(path, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
}

/// study option sigma: one value for all outputs or one per output.
std::vector<double> sigma_for(const StudyOptions& options, std::size_t outputs, const std::string& path) {
  std::vector<double> sigma = options.sigma;
  if (sigma.size() == 1) sigma.assign(outputs, sigma[0]);
  if (sigma.size() != outputs)
    throw UsageError(fmt::format("study option 'sigma' has {} values for the {} measured outputs of {}",
                                 sigma.size(), outputs, path));
  return sigma;
}

/// Measurements from a .mat file: the columns named by study option outputs.
runtime::MeasurementTable mat_measurements(const std::string& path, const runtime::ModelInfo& info,
                                           const StudyOptions& options) {
  runtime::InputTable table;
  try {
    table = runtime::read_result_table(path);
  } catch (const runtime::InputFileError& e) {
    throw UsageError(e.what());
  }
  if (options.outputs.empty())
    throw UsageError(path + ": error: a .mat measurement file needs study option 'outputs' naming the "
                            "measured variables (the file's vectors or variables of those names)");
  runtime::MeasurementTable t;
  t.times = table.times;
  t.values.resize(static_cast<Eigen::Index>(t.times.size()), static_cast<Eigen::Index>(options.outputs.size()));
  for (std::size_t c = 0; c < options.outputs.size(); ++c) {
    const std::string& name = options.outputs[c];
    const auto it = std::find(table.names.begin(), table.names.end(), name);
    if (it == table.names.end()) throw UsageError(path + ": error: no vector or variable '" + name + "'");
    const auto k = info.output_index(name);
    if (!k) throw UsageError(path + ": error: '" + name + "' is not a variable of the model");
    t.outputs.push_back(*k);
    const auto& column = table.columns[static_cast<std::size_t>(it - table.names.begin())];
    for (std::size_t r = 0; r < t.times.size(); ++r)
      t.values(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = column[r];
  }
  t.sigma = sigma_for(options, t.outputs.size(), path);
  return t;
}

}  // namespace

runtime::Inputs inputs_of(const std::map<std::size_t, std::shared_ptr<const runtime::InputSignal>>& m,
                          std::size_t n) {
  runtime::Inputs in;
  for (std::size_t i = 0; i < n; ++i) in.add(runtime::shared_input(m.at(i)));
  return in;
}

std::string resolve_path(const std::string& study_file, const std::string& path) {
  std::error_code ec;
  if (fs::path(path).is_absolute() || fs::exists(path, ec) || study_file.empty()) return path;
  return (fs::path(study_file).parent_path() / path).string();
}

runtime::MeasurementTable read_measurements(const std::string& path, const runtime::ModelInfo& info,
                                            const StudyOptions& options) {
  if (runtime::is_mat_file(path)) return mat_measurements(path, info, options);
  std::ifstream in(path);
  if (!in) throw UsageError(path + ": error: cannot read the measurement file");
  std::string line;
  std::size_t line_no = 0;
  std::vector<std::string> header;
  std::vector<int> column_output;  // per CSV column after time: index into table.outputs or -1
  runtime::MeasurementTable t;
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    const auto fields = split(line, ',');
    if (header.empty()) {
      header = fields;
      if (header.empty() || header[0] != "time")
        throw UsageError(fmt::format("{}:{}: error: the header must start with 'time'", path, line_no));
      for (std::size_t c = 1; c < header.size(); ++c) {
        const bool wanted = options.outputs.empty() ||
                            std::find(options.outputs.begin(), options.outputs.end(), header[c]) !=
                                options.outputs.end();
        const auto k = info.output_index(header[c]);
        if (wanted && !k)
          throw UsageError(fmt::format("{}:{}: error: column '{}' is not a variable of the model",
                                       path, line_no, header[c]));
        column_output.push_back(wanted ? static_cast<int>(t.outputs.size()) : -1);
        if (wanted) t.outputs.push_back(*k);
      }
      continue;
    }
    if (fields.size() > header.size() || fields.empty())
      throw UsageError(fmt::format("{}:{}: error: expected {} fields", path, line_no, header.size()));
    std::vector<double> row(t.outputs.size() + 1, std::nan(""));
    for (std::size_t c = 0; c < fields.size(); ++c) {
      if (c > 0 && column_output[c - 1] < 0) continue;
      const std::string f = fields[c];
      double v = std::nan("");
      if (!f.empty() && f != "NaN" && f != "nan") v = number(f, fmt::format("{}:{}", path, line_no));
      if (c == 0 && !std::isfinite(v))
        throw UsageError(fmt::format("{}:{}: error: missing time", path, line_no));
      row[c == 0 ? 0 : static_cast<std::size_t>(column_output[c - 1]) + 1] = v;
    }
    rows.push_back(std::move(row));
  }
  if (rows.empty() || t.outputs.empty())
    throw UsageError(path + ": error: no measured outputs or no rows");
  t.values.resize(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(t.outputs.size()));
  for (std::size_t k = 0; k < rows.size(); ++k) {
    t.times.push_back(rows[k][0]);
    for (std::size_t r = 0; r < t.outputs.size(); ++r)
      t.values(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(r)) = rows[k][r + 1];
  }
  t.sigma = sigma_for(options, t.outputs.size(), path);
  return t;
}

std::map<std::size_t, std::shared_ptr<const runtime::InputSignal>> given_inputs(
    const runtime::ModelInfo& info, const std::string& spec, const std::string& study_file) {
  std::map<std::size_t, std::shared_ptr<const runtime::InputSignal>> out;
  for (const auto& item : split(spec, ';')) {
    if (item.empty()) continue;
    auto [name, signal] = split_assignment(item, "given input");
    const auto k = info.input_index(name);
    if (!k) throw UsageError("study option inputs: the model has no input '" + name + "'");
    if (out.contains(*k)) throw UsageError("study option inputs: input '" + name + "' is given twice");
    const auto colon = signal.find(':');
    if (colon != std::string::npos && (signal.starts_with("csv:") || signal.starts_with("pwc:")))
      signal = signal.substr(0, colon + 1) + resolve_path(study_file, signal.substr(colon + 1));
    out[*k] = parse_signal(name, signal);
  }
  return out;
}

std::map<std::size_t, std::shared_ptr<const runtime::InputSignal>> experiment_inputs(
    const runtime::ModelInfo& info, const std::string& spec, const std::string& study_file) {
  auto out = given_inputs(info, spec, study_file);
  for (std::size_t i = 0; i < info.inputs.size(); ++i)
    if (!out.contains(i))
      throw UsageError("estimation: input '" + info.inputs[i].name +
                       "' has no signal (study option inputs = {\"" + info.inputs[i].name +
                       "=pwc:designed_input.csv\", ...}, one entry per experiment)");
  return out;
}

void write_error_summary(const std::string& dir, const runtime::ModelInfo& info, const std::string& message,
                         const json& extra) {
  fs::create_directories(dir);
  json summary{{"status", "error"}, {"message", message}, {"model", info.name}};
  for (const auto& [key, value] : extra.items()) summary[key] = value;
  write_json((fs::path(dir) / "summary.json").string(), summary);
}

void write_optimization_outputs(const std::string& dir, const runtime::ModelInfo& info,
                                const runtime::OptimalControlProblem& problem,
                                const runtime::OptimizationResult& result, const json& extra) {
  runtime::write_optimization_result(dir, result, info);
  const std::string path = (fs::path(dir) / "summary.json").string();
  json summary = json::parse(runtime::optimization_summary_json(result, info));
  summary["model"] = info.name;
  summary["horizon"] = {problem.t0, problem.tf};
  summary["collocation"] = {{"n_e", problem.collocation.n_e}, {"n_cp", problem.collocation.n_cp}};
  for (const auto& [key, value] : extra.items()) summary[key] = value;
  write_json(path, summary);
}

json design_json(const runtime::ModelInfo& info, const runtime::InputDesignProblem& d,
                 const runtime::InputDesignResult& r) {
  static const char* names[] = {"A", "T", "D", "E"};
  json j;
  json params = json::array();
  for (std::size_t k : d.parameters) params.push_back(info.parameters[k].name);
  j["design"] = {
      {"criterion", names[static_cast<int>(d.criterion)]},
      {"parameters", params},
      {"measurements", d.measurements.times.size()},
      {"fisher_collocation", matrix_json(r.fisher_collocation)},
      {"fisher_resimulated", matrix_json(r.fisher_resimulated)},
      {"information_collocation", number_json(r.information_collocation)},
      {"information_resimulated", number_json(r.information_resimulated)},
  };
  json starts = json::array();
  for (double v : r.start_information) starts.push_back(number_json(v));
  j["design"]["information_per_start"] = starts;
  json attempts = json::array();
  for (const auto& a : r.attempts)
    attempts.push_back(
        {{"hessian", a.hessian == runtime::HessianMode::limited_memory ? "limited_memory" : "exact"},
         {"status", std::string(runtime::to_string(a.status))},
         {"iterations", a.iterations},
         {"kkt", {{"primal_infeasibility", number_json(a.kkt.primal_infeasibility)},
                  {"dual_infeasibility", number_json(a.kkt.dual_infeasibility)},
                  {"complementarity", number_json(a.kkt.complementarity)}}},
         {"solve_seconds", a.solve_seconds},
         {"information_collocation", number_json(a.information_collocation)},
         {"information_resimulated", number_json(a.information_resimulated)},
         {"kept", a.kept}});
  j["design"]["attempts"] = attempts;
  return j;
}

void write_designed_input(const std::string& dir, const runtime::ModelInfo& info,
                          const runtime::OptimalControlProblem& problem,
                          const runtime::OptimizationResult& result) {
  std::vector<std::string> names;
  for (const auto& c : problem.controls) names.push_back(info.inputs[c.input].name);
  runtime::ResultTable t(names);
  const auto& tau = result.element_times;
  for (std::size_t e = 0; e + 1 < tau.size(); ++e) {
    std::vector<double> row;
    for (const auto& values : result.control_values) row.push_back(values[e]);
    t.add_row(tau[e], row);
  }
  if (!tau.empty() && !result.control_values.empty() && !result.control_values[0].empty()) {
    std::vector<double> last;
    for (const auto& values : result.control_values) last.push_back(values.back());
    t.add_row(tau.back(), last);
  }
  runtime::write_csv_atomic((fs::path(dir) / "designed_input.csv").string(), t);
}

void write_estimation_outputs(const std::string& dir, runtime::Model& model,
                              const runtime::EstimationProblem& e,
                              const runtime::EstimationResult& r) {
  const runtime::ModelInfo& info = model.info();
  // The runtime's summary and trajectories_<e>.csv, then the study's keys on
  // top of that summary (as write_optimization_outputs does).
  runtime::write_estimation_result(dir, r);
  json j = json::parse(runtime::estimation_summary_json(r));
  j["model"] = info.name;
  j["confidence"] = e.confidence;
  j["t_quantile"] = r.t_quantile;
  json est = json::array();
  for (std::size_t k = 0; k < r.estimate.size(); ++k)
    est.push_back({{"name", r.names[k]},
                   {"estimate", r.estimate[k]},
                   {"standard_error", k < r.standard_error.size() ? number_json(r.standard_error[k]) : json()},
                   {"ci", k < r.confidence_interval.size()
                              ? json{number_json(r.confidence_interval[k].lo),
                                     number_json(r.confidence_interval[k].hi)}
                              : json()}});
  j["estimates"] = est;
  j["fisher"] = matrix_json(r.fisher);
  write_json((fs::path(dir) / "summary.json").string(), j);
  // fit.csv: the model at the estimate on each experiment's sample times.
  std::vector<std::string> names{"experiment"};
  const auto& outs = e.experiments.front().data.outputs;
  for (std::size_t o : outs) names.push_back(info.outputs[o].name + ":model");
  for (std::size_t o : outs) names.push_back(info.outputs[o].name + ":data");
  runtime::ResultTable fit(names);
  runtime::SimulationOptions so;
  so.relative_tolerance = 1e-8;
  for (std::size_t x = 0; x < e.experiments.size(); ++x) {
    const auto& ex = e.experiments[x];
    std::vector<double> grid{ex.t0};
    for (double t : ex.data.times) if (t > ex.t0) grid.push_back(t);
    const auto sim = runtime::simulate(model, inputs_of(ex.inputs, info.inputs.size()),
                                       r.parameters.empty() ? info.default_parameters() : r.parameters,
                                       runtime::OutputGrid::at(grid), so);
    for (std::size_t k = 0; k < ex.data.times.size() && sim.ok(); ++k) {
      const std::size_t row = std::min(k + (ex.data.times[0] > ex.t0 ? 1 : 0), sim.trajectory.rows() - 1);
      std::vector<double> values{static_cast<double>(x + 1)};
      for (std::size_t o : outs)
        values.push_back(sim.trajectory.at(row, info.states.size() + o));
      for (std::size_t c = 0; c < outs.size() && c < static_cast<std::size_t>(ex.data.values.cols()); ++c)
        values.push_back(ex.data.values(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(c)));
      values.resize(names.size(), std::nan(""));
      fit.add_row(ex.data.times[k], values);
    }
  }
  runtime::write_csv_atomic((fs::path(dir) / "fit.csv").string(), fit);
}

void print_estimates(std::ostream& os, const runtime::EstimationResult& r) {
  os << fmt::format("morun: estimation {}: chi^2 = {:.6g} on {} degrees of freedom (s^2 = {:.4g})\n",
                    runtime::to_string(r.status), r.chi_square, r.degrees_of_freedom,
                    r.residual_variance);
  for (std::size_t k = 0; k < r.estimate.size(); ++k) {
    os << fmt::format("morun:   {} = {:.6g}", r.names[k], r.estimate[k]);
    if (k < r.confidence_interval.size())
      os << fmt::format("  (se {:.3g}, CI [{:.6g}, {:.6g}])", r.standard_error[k],
                        r.confidence_interval[k].lo, r.confidence_interval[k].hi);
    os << "\n";
  }
  for (const auto& w : r.warnings) os << "morun: warning: " << w << "\n";
  if (!r.message.empty()) os << "morun: " << r.message << "\n";
}

}  // namespace mo::tools
