// task = "monte_carlo": how good is the estimator under each input?
//
// For every input case (study option `inputs`, one entry each) and every seed
// 1..seeds: simulate the plant accurately at the true parameters (the study's
// values, --set), sample the measured outputs on the design's sample times,
// add white noise σ, estimate the free parameters by collocation from their
// initial guesses, and record the estimate and its confidence interval. Per
// case the summary gives the mean and spread of the estimates beside the
// Cramér–Rao bound sqrt(diag F⁻¹) (F from the sensitivities at the truth) and
// the coverage of the confidence intervals. The runs are independent tasks
// of the parallel runner (parallel_runner.hpp: -j worker processes, MPI
// ranks); their results are gathered in (case, seed) order, so the files do
// not depend on how many processes solved them.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <map>
#include <random>

#include "mo/runtime/result.hpp"
#include "mo/runtime/simulate.hpp"
#include "study_internal.hpp"
#include "parallel_runner.hpp"
#include "study_output.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace mo::tools::detail {

namespace {

/// Noisy samples of the measured outputs from an accurate simulation.
runtime::MeasurementTable noisy_data(runtime::Model& model, const runtime::Inputs& inputs,
                                     const std::vector<double>& p, double t0,
                                     const runtime::MeasurementDesign& m, std::mt19937_64& rng) {
  runtime::SimulationOptions so;
  so.relative_tolerance = 1e-10;
  so.absolute_tolerance = 1e-12;
  std::vector<double> grid{t0};
  grid.insert(grid.end(), m.times.begin(), m.times.end());
  const auto sim = runtime::simulate(model, inputs, p, runtime::OutputGrid::at(grid), so);
  if (!sim.ok()) throw std::runtime_error("monte_carlo: the data simulation failed: " + sim.message);
  std::normal_distribution<double> noise(0.0, 1.0);
  runtime::MeasurementTable t;
  t.times = m.times;
  t.outputs = m.outputs;
  t.sigma = m.sigma;
  t.values.resize(static_cast<Eigen::Index>(m.times.size()), static_cast<Eigen::Index>(m.outputs.size()));
  const std::size_t nx = model.info().states.size();
  for (std::size_t k = 0; k < m.times.size(); ++k)
    for (std::size_t r = 0; r < m.outputs.size(); ++r)
      t.values(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(r)) =
          sim.trajectory.at(k + 1, nx + m.outputs[r]) + m.sigma[r] * noise(rng);
  return t;
}

struct CaseStats {
  std::string input;
  std::vector<std::vector<double>> estimates;  ///< per successful seed
  std::vector<bool> covered;                   ///< per successful seed, all parameters in their CI
  int failures = 0;
  std::map<std::string, int> failed_with;  ///< failed runs per reason (the estimation's status)
  Eigen::MatrixXd fisher;
};

/// "iteration_limit ×3, infeasible ×1".
std::string reasons_text(const std::map<std::string, int>& reasons) {
  std::string out;
  for (const auto& [why, count] : reasons) out += fmt::format("{}{} ×{}", out.empty() ? "" : ", ", why, count);
  return out;
}

json case_json(const CaseStats& c, const std::vector<std::string>& names,
               const std::vector<double>& truth) {
  json j;
  j["input"] = c.input;
  j["runs"] = c.estimates.size();
  j["failures"] = c.failures;
  if (!c.failed_with.empty()) j["failed_with"] = c.failed_with;
  std::size_t covered = 0;
  for (bool b : c.covered) covered += b ? 1 : 0;
  // No estimate, no statistic: null rather than numbers of an empty sample.
  j["ci_coverage"] = c.covered.empty() ? json(nullptr) : json(double(covered) / double(c.covered.size()));
  Eigen::MatrixXd inv;
  if (c.fisher.size() > 0 && c.fisher.determinant() > 0) inv = c.fisher.inverse();
  json params = json::array();
  for (std::size_t k = 0; k < names.size(); ++k) {
    double mean = 0, sq = 0;
    for (const auto& e : c.estimates) mean += e[k];
    mean /= std::max<std::size_t>(1, c.estimates.size());
    for (const auto& e : c.estimates) sq += (e[k] - mean) * (e[k] - mean);
    const double sd = c.estimates.size() > 1 ? std::sqrt(sq / double(c.estimates.size() - 1)) : 0.0;
    const double crb = inv.size() ? std::sqrt(inv(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k))) : NAN;
    const bool any = !c.estimates.empty();
    params.push_back({{"name", names[k]}, {"true", truth[k]}, {"mean", any ? json(mean) : json(nullptr)},
                      {"std", c.estimates.size() > 1 ? json(sd) : json(nullptr)},
                      {"cramer_rao", std::isfinite(crb) ? json(crb) : json(nullptr)},
                      {"bias", any ? json(mean - truth[k]) : json(nullptr)}});
  }
  j["parameters"] = params;
  return j;
}

/// One Monte-Carlo run (case c, seed): noisy data from an accurate simulation
/// at the truth, then the estimate and its confidence interval, as JSON
/// {ok, estimate, lo, hi, solve, simulate} (the last two in seconds).
json monte_carlo_run(Study& s, const std::vector<runtime::FreeParameter>& free,
                     const std::map<std::size_t, std::shared_ptr<const runtime::InputSignal>>& signals,
                     const runtime::MeasurementDesign& m, int seed, bool isolated) {
  const runtime::ModelInfo& info = s.info();
  const std::vector<double> truth_all = parameter_values(info, s.cli);
  std::mt19937_64 rng(static_cast<unsigned long>(seed));
  auto started = std::chrono::steady_clock::now();
  runtime::EstimationProblem e;
  runtime::EstimationExperiment ex;
  ex.t0 = s.problem.t0;
  ex.inputs = signals;
  ex.data = noisy_data(*s.built.model, inputs_of(signals, info.inputs.size()), truth_all, s.problem.t0, m, rng);
  e.experiments.push_back(std::move(ex));
  double simulate_seconds = seconds_since(started), solve_seconds = 0;
  e.parameters = free;
  e.parameter_values = truth_all;
  e.collocation = collocation_options(s.opt);
  e.solver = solver_options(s);
  e.solver.log_file.clear();  // concurrent runs would share one log
  e.solver.progress = isolated ? nullptr : solver_progress(s.cli.run);
  e.confidence = s.opt.confidence;
  started = std::chrono::steady_clock::now();
  const auto r = s.estimate ? s.estimate(e) : runtime::estimate_parameters(*s.built.model, e);
  solve_seconds += seconds_since(started);
  for (const auto& x : r.experiments) solve_seconds -= x.timings.resimulation, simulate_seconds += x.timings.resimulation;
  const bool converged =
      r.status == runtime::OptimizationStatus::success || r.status == runtime::OptimizationStatus::acceptable;
  const bool ok = converged && r.confidence_interval.size() == free.size();
  json j{{"ok", ok}, {"solve", solve_seconds}, {"simulate", simulate_seconds}};
  if (!ok) {
    j["why"] = converged ? std::string("no confidence interval") : std::string(runtime::to_string(r.status));
    return j;
  }
  j["estimate"] = r.estimate;
  std::vector<double> lo, hi;
  for (const auto& ci : r.confidence_interval) lo.push_back(ci.lo), hi.push_back(ci.hi);
  j["lo"] = lo, j["hi"] = hi;
  return j;
}

}  // namespace

int monte_carlo(Study& s) {
  const runtime::ModelInfo& info = s.info();
  const auto free = free_parameters(s);
  if (free.empty()) throw UsageError("monte_carlo needs parameters declared free = true");
  if (s.opt.inputs.empty()) throw UsageError("monte_carlo needs study option 'inputs' (one per case)");
  const std::vector<double> truth_all = parameter_values(info, s.cli);
  std::vector<std::size_t> idx;
  std::vector<std::string> names;
  std::vector<double> truth;
  for (const auto& f : free) {
    idx.push_back(f.parameter);
    names.push_back(info.parameters[f.parameter].name);
    truth.push_back(truth_all[f.parameter]);
  }
  const runtime::MeasurementDesign m = measurements(s, s.problem.t0, s.problem.tf);
  RunContext* run = s.cli.run;
  Progress* progress = run ? run->progress : nullptr;
  if (progress) progress->stage("monte carlo");
  double simulate_seconds = 0, solve_seconds = 0;
  const std::size_t n_cases = s.opt.inputs.size(), seeds = static_cast<std::size_t>(s.opt.seeds);
  std::vector<std::map<std::size_t, std::shared_ptr<const runtime::InputSignal>>> signals;
  std::vector<CaseStats> stats(n_cases);
  for (std::size_t c = 0; c < n_cases; ++c) {
    signals.push_back(experiment_inputs(info, s.opt.inputs[c], s.cli.study_file));
    stats[c].input = s.opt.inputs[c];
    const auto started = std::chrono::steady_clock::now();
    stats[c].fisher = runtime::fisher_information(*s.built.model, inputs_of(signals[c], info.inputs.size()),
                                                  truth_all, s.problem.t0, m, idx);
    simulate_seconds += seconds_since(started);
  }
  // Every (case, seed) is one task of the parallel runner: k = case·seeds + seed − 1.
  std::size_t finished = 0;
  ParallelTasks tasks;
  tasks.count = n_cases * seeds;
  tasks.jobs = s.cli.jobs;
  tasks.solve = [&](std::size_t k, bool isolated) {
    if (!isolated && progress)
      progress->context(fmt::format("case {} of {}, {} of {}", k / seeds + 1, n_cases, k % seeds + 1, seeds));
    return monte_carlo_run(s, free, signals[k / seeds], m, static_cast<int>(k % seeds + 1), isolated);
  };
  tasks.done = [&](std::size_t, const json&) {
    if (progress && s.cli.jobs > 1)
      progress->context(fmt::format("{} of {} runs done ({} processes)", ++finished, tasks.count, s.cli.jobs));
  };
  const std::vector<json> results = run_parallel(tasks);
  if (results.empty()) return 0;  // an MPI rank other than 0: rank 0 writes the results
  std::string csv = "case,seed";  // one row per successful estimate
  for (const auto& n : names) csv += fmt::format(",{0},{0}:lo,{0}:hi", n);
  csv += "\n";
  for (std::size_t k = 0; k < results.size(); ++k) {
    const json& j = results[k];
    CaseStats& st = stats[k / seeds];
    solve_seconds += j.value("solve", 0.0), simulate_seconds += j.value("simulate", 0.0);
    if (!j.value("ok", false)) {
      ++st.failures;
      ++st.failed_with[j.value("why", std::string("unknown"))];
      continue;
    }
    const auto est = j.at("estimate").get<std::vector<double>>();
    const auto lo = j.at("lo").get<std::vector<double>>(), hi = j.at("hi").get<std::vector<double>>();
    bool in = true;
    csv += fmt::format("{},{}", k / seeds + 1, k % seeds + 1);
    for (std::size_t p = 0; p < names.size(); ++p) {
      in = in && lo[p] <= truth[p] && truth[p] <= hi[p];
      csv += fmt::format(",{},{},{}", est[p], lo[p], hi[p]);
    }
    csv += "\n";
    st.estimates.push_back(est);
    st.covered.push_back(in);
  }
  json cases = json::array();
  for (std::size_t c = 0; c < n_cases; ++c) {
    const json cj = case_json(stats[c], names, truth);
    const std::string line = fmt::format("morun: monte_carlo case {} ({}): {}", c + 1, stats[c].input, cj.dump());
    if (progress)
      progress->println(line);
    else
      std::cerr << line << "\n";
    cases.push_back(cj);
  }
  if (progress) progress->end_stage();
  if (run) run->timings.add("solve", solve_seconds), run->timings.add("simulate", simulate_seconds);
  runtime::write_file_atomic((fs::path(s.cli.output) / "monte_carlo.csv").string(),
                             [&](std::ostream& os) { os << csv; });
  // A case without a single estimate has no statistic: the study failed.
  std::string message;
  for (std::size_t c = 0; c < n_cases; ++c)
    if (stats[c].estimates.empty())
      message += fmt::format("{}case {}: every run failed ({})", message.empty() ? "" : "; ", c + 1,
                             reasons_text(stats[c].failed_with));
  json summary{{"model", info.name}, {"seeds", s.opt.seeds}, {"cases", cases},
               {"status", message.empty() ? "success" : "failed"}};
  if (!message.empty()) summary["message"] = message;
  runtime::write_file_atomic((fs::path(s.cli.output) / "summary.json").string(),
                             [&](std::ostream& os) { os << summary.dump(2) << "\n"; });
  if (message.empty()) return 0;
  std::cerr << "morun: error: monte_carlo: " << message << "\n";
  return 1;
}

}  // namespace mo::tools::detail
