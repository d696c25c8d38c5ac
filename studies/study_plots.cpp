// Study figures; see study_plots.hpp.
#include "study_plots.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "mo/runtime/result.hpp"
#include "mo/runtime/simulate.hpp"
#include "plot.hpp"
#include "study_output.hpp"

namespace fs = std::filesystem;

namespace mo::tools {

namespace {

constexpr std::size_t kIntervals = 500;

std::string path_in(const std::string& dir, const std::string& file) {
  return (fs::path(dir) / file).string();
}

void add_bounds(Panel& p, double lo, double hi) {
  for (double v : {lo, hi})
    if (std::isfinite(v)) p.bounds.push_back(v);
}

/// (t, value) targets of point constraints on state `name`.
std::vector<std::pair<double, double>> targets_of(const std::string& name, const ProblemOutputs& outputs) {
  std::vector<std::pair<double, double>> out;
  for (const ProblemConstraint& c : outputs.constraints) {
    if (c.variable != name || !c.time) continue;
    if (std::isfinite(c.lo)) out.emplace_back(*c.time, c.lo);
    if (std::isfinite(c.hi) && c.hi != c.lo) out.emplace_back(*c.time, c.hi);
  }
  return out;
}

std::string sensitivity_name(const std::string& y, const std::string& p) {
  return "d(" + y + ")/d(" + p + ")";
}

}  // namespace

void plot_optimization(const std::string& dir, const runtime::ModelInfo& info,
                       const runtime::OptimalControlProblem& problem, const ProblemOutputs& outputs,
                       const std::string& title) {
  const std::string traj = path_in(dir, "trajectories.csv"), resim = path_in(dir, "resimulated.csv");
  Figure states;
  states.title = info.name + ": " + title + " - states (line: collocation, dotted: re-simulated)";
  states.panel_height = 190;
  for (std::size_t i = 0; i < info.num_base_states(); ++i) {
    const auto& x = info.states[i];
    Panel p;
    p.ylabel = axis_label(x.name, x.unit);
    p.series.push_back({traj, 1, i + 2, 0, x.name, SeriesStyle::line, {}});
    p.series.push_back({resim, 1, i + 2, 0, x.name + " re-simulated", SeriesStyle::dotted, {}});
    runtime::Bounds b{x.min, x.max};
    if (auto it = problem.state_bounds.find(i); it != problem.state_bounds.end()) b = it->second;
    add_bounds(p, b.lo, b.hi);
    p.targets = targets_of(x.name, outputs);
    states.panels.push_back(std::move(p));
  }
  render_figure(states, dir, "states");
  Figure inputs;
  inputs.title = info.name + ": " + title + " - inputs";
  inputs.panel_height = 220;
  for (const runtime::FreeControl& c : problem.controls) {
    const auto& u = info.inputs[c.input];
    Panel p;
    p.ylabel = axis_label(u.name, u.unit);
    p.series.push_back({traj, 1, info.states.size() + c.input + 2, 0, u.name, SeriesStyle::steps, {}});
    add_bounds(p, c.bounds.lo, c.bounds.hi);
    inputs.panels.push_back(std::move(p));
  }
  render_figure(inputs, dir, "inputs");
}

bool write_design_sensitivities(const std::string& dir, runtime::Model& model,
                                const runtime::InputDesignProblem& d, const runtime::OptimizationResult& r) {
  const runtime::ModelInfo& info = model.info();
  if (r.element_times.empty() || d.parameters.empty()) return false;
  runtime::SimulationOptions so;
  so.relative_tolerance = 1e-8;
  so.sensitivities.method = runtime::SensitivityMethod::cvodes_analytic;
  so.sensitivities.parameters = d.parameters;
  const auto sim = runtime::simulate(
      model, runtime::optimal_inputs(d.ocp, r, info.inputs.size()),
      r.parameters.empty() ? info.default_parameters() : r.parameters,
      runtime::OutputGrid::uniform(d.ocp.t0, d.ocp.tf, kIntervals), so);
  if (!sim.ok() || sim.output_sensitivities.size() != sim.trajectory.rows()) return false;
  std::vector<std::string> names;
  for (std::size_t y : d.measurements.outputs)
    for (std::size_t p : d.parameters) names.push_back(sensitivity_name(info.outputs[y].name, info.parameters[p].name));
  runtime::ResultTable t(names);
  for (std::size_t k = 0; k < sim.trajectory.rows(); ++k) {
    std::vector<double> row;
    for (std::size_t y : d.measurements.outputs)
      for (std::size_t j = 0; j < d.parameters.size(); ++j)
        row.push_back(sim.output_sensitivities[k](Eigen::Index(y), Eigen::Index(j)));
    t.add_row(sim.trajectory.times()[k], row);
  }
  runtime::write_csv_atomic(path_in(dir, "sensitivities.csv"), t);
  return true;
}

void plot_design_sensitivities(const std::string& dir, const runtime::ModelInfo& info,
                               const runtime::InputDesignProblem& d) {
  std::vector<PlotVariable> vars;
  std::size_t column = 2;
  for (std::size_t y : d.measurements.outputs)
    for (std::size_t p : d.parameters)
      vars.push_back({column++, sensitivity_name(info.outputs[y].name, info.parameters[p].name),
                      quotient_unit(info.outputs[y].unit, info.parameters[p].unit)});
  Figure f;
  f.title = info.name + ": sensitivities of the measured outputs under the designed input";
  f.panels = panels_by_unit(path_in(dir, "sensitivities.csv"), vars);
  render_figure(f, dir, "sensitivities");
}

namespace {

/// "NAME.csv" for experiment 1, "NAME_<k>.csv" for experiment k ≥ 2 (the
/// numbering of fit.csv's experiment column).
std::string per_experiment(const std::string& dir, const std::string& name, std::size_t k,
                           const std::string& extension) {
  return path_in(dir, (k == 1 ? name : fmt::format("{}_{}", name, k)) + extension);
}

/// One experiment's prediction file; false if its simulation fails.
bool write_experiment_prediction(const std::string& file, runtime::Model& model,
                                 const runtime::EstimationProblem& e,
                                 const runtime::EstimationExperiment& ex,
                                 const runtime::EstimationResult& r) {
  const runtime::ModelInfo& info = model.info();
  if (ex.data.times.empty()) return false;
  std::vector<std::size_t> params;
  for (const auto& fp : e.parameters) params.push_back(fp.parameter);
  const Eigen::MatrixXd& cov = r.covariance;
  const bool band = cov.rows() == Eigen::Index(params.size()) && !params.empty();
  runtime::SimulationOptions so;
  so.relative_tolerance = 1e-8;
  if (band) {
    so.sensitivities.method = runtime::SensitivityMethod::cvodes_analytic;
    so.sensitivities.parameters = params;
  }
  const auto sim = runtime::simulate(model, inputs_of(ex.inputs, info.inputs.size()),
                                     r.parameters.empty() ? info.default_parameters() : r.parameters,
                                     runtime::OutputGrid::uniform(ex.t0, ex.data.times.back(), kIntervals), so);
  if (!sim.ok()) return false;
  std::vector<std::string> names;
  for (std::size_t y : ex.data.outputs)
    for (const char* part : {":model", ":lo", ":hi"}) names.push_back(info.outputs[y].name + part);
  runtime::ResultTable t(names);
  for (std::size_t k = 0; k < sim.trajectory.rows(); ++k) {
    std::vector<double> row;
    for (std::size_t y : ex.data.outputs) {
      const double value = sim.trajectory.at(k, info.states.size() + y);
      double half = std::nan("");
      if (band && k < sim.output_sensitivities.size()) {
        const Eigen::RowVectorXd s = sim.output_sensitivities[k].row(Eigen::Index(y));
        half = r.t_quantile * std::sqrt(std::max(0.0, double(s * cov * s.transpose())));
      }
      row.insert(row.end(), {value, value - half, value + half});
    }
    t.add_row(sim.trajectory.times()[k], row);
  }
  runtime::write_csv_atomic(file, t);
  return true;
}

/// The fit figure of experiment k (1-based): measurements from fit.csv
/// (rows whose experiment column is k), the prediction and its band.
void plot_experiment_fit(const std::string& dir, const runtime::ModelInfo& info,
                         const runtime::EstimationProblem& e, const std::string& estimate,
                         std::size_t k) {
  const auto& outs = e.experiments.front().data.outputs;  // fit.csv's columns
  const std::size_t n = outs.size();
  const std::string fit = path_in(dir, "fit.csv"), prediction = per_experiment(dir, "prediction", k, ".csv");
  const bool have_prediction = fs::exists(prediction) && e.experiments[k - 1].data.outputs == outs;
  Figure f;
  f.title = fmt::format("{}: measurements and the model at the estimate ({}){}", info.name, estimate,
                        e.experiments.size() > 1 ? fmt::format(", experiment {}", k) : "");
  for (std::size_t c = 0; c < n; ++c) {
    const auto& y = info.outputs[outs[c]];
    Panel p;
    p.ylabel = axis_label(y.name, y.unit);
    Series data{fit, 1, 0, 0, y.name + " measured", SeriesStyle::points, {}};
    data.y_expr = fmt::format("($2 == {} ? ${} : NaN)", k, c + 3 + n);
    if (have_prediction) {
      p.series.push_back({prediction, 1, 3 * c + 3, 3 * c + 4,
                          fmt::format("{:g} % confidence band", 100 * e.confidence), SeriesStyle::band, {}});
      p.series.push_back(data);
      p.series.push_back({prediction, 1, 3 * c + 2, 0, y.name + " model", SeriesStyle::line, {}});
    } else {
      p.series.push_back(data);
      Series model{fit, 1, 0, 0, y.name + " model", SeriesStyle::line, {}};
      model.y_expr = fmt::format("($2 == {} ? ${} : NaN)", k, c + 3);
      p.series.push_back(model);
    }
    f.panels.push_back(std::move(p));
  }
  render_figure(f, dir, k == 1 ? "fit" : fmt::format("fit_{}", k));
}

}  // namespace

bool write_prediction(const std::string& dir, runtime::Model& model, const runtime::EstimationProblem& e,
                      const runtime::EstimationResult& r) {
  bool all = !e.experiments.empty();
  for (std::size_t k = 0; k < e.experiments.size(); ++k)
    all = write_experiment_prediction(per_experiment(dir, "prediction", k + 1, ".csv"), model, e,
                                      e.experiments[k], r) && all;
  return all;
}

void plot_fit(const std::string& dir, const runtime::ModelInfo& info, const runtime::EstimationProblem& e,
              const runtime::EstimationResult& r) {
  std::string estimate;
  for (std::size_t k = 0; k < r.estimate.size(); ++k)
    estimate += fmt::format("{}{} = {:.5g}", k ? ", " : "", r.names[k], r.estimate[k]);
  for (std::size_t k = 1; k <= e.experiments.size(); ++k) plot_experiment_fit(dir, info, e, estimate, k);
}

}  // namespace mo::tools
