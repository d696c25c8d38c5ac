// Multistart input design; see multistart.hpp.
#include "multistart.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>

#include "design_result_json.hpp"
#include "parallel_runner.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace mo::tools {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

json number_json(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

/// The problem of start k: its guesses replace the controls' own.
runtime::InputDesignProblem start_problem(const runtime::InputDesignProblem& d, const DesignStart& start,
                                          const std::string& log_file, bool isolated) {
  runtime::InputDesignProblem one = d;
  one.starts.clear();
  one.on_start = nullptr;
  for (std::size_t c = 0; c < one.ocp.controls.size() && c < start.guesses.size(); ++c)
    if (start.guesses[c]) one.ocp.controls[c].initial_guess = start.guesses[c];
  one.ocp.solver.log_file = log_file;
  if (isolated) one.ocp.solver.progress = nullptr;
  return one;
}

StartOutcome outcome_of(std::size_t k, const DesignStart& start, const json& j,
                        const runtime::InputDesignResult* r) {
  StartOutcome o{k, start.origin, start.label, "error", false, 0, nan, nan, nan, 0.0, "", "", 0};
  o.seconds = j.value("seconds", 0.0);
  if (!r) {
    o.error = j.value("error", std::string("no result"));
    return o;
  }
  o.status = std::string(runtime::to_string(r->optimization.status));
  o.converged = r->optimization.ok();
  o.iterations = r->optimization.iterations;
  o.objective = r->optimization.objective;
  o.information_collocation = r->information_collocation;
  o.information_resimulated = r->information_resimulated;
  if (!std::isfinite(o.information_collocation)) o.converged = false;
  o.attempts = r->attempts.size();
  for (const auto& a : r->attempts)
    if (a.kept) o.hessian = a.hessian == runtime::HessianMode::limited_memory ? "limited_memory" : "exact";
  return o;
}

/// Is `a` better than the best so far (`best`, or none)? Ties keep the lower start.
bool better(const StartOutcome& a, const StartOutcome* best) {
  if (!a.converged) return false;
  if (!best || !best->converged) return true;
  return a.information_collocation > best->information_collocation ||
         (a.information_collocation == best->information_collocation && a.index < best->index);
}

std::string log_file(const MultistartSettings& s, std::size_t k) {
  return (fs::path(s.output_dir) / "starts" / fmt::format("ipopt_{}.log", k + 1)).string();
}

}  // namespace

std::vector<LocalOptimum> cluster_optima(const std::vector<StartOutcome>& starts, double tolerance) {
  std::vector<const StartOutcome*> converged;
  for (const auto& s : starts)
    if (s.converged) converged.push_back(&s);
  std::stable_sort(converged.begin(), converged.end(), [](const StartOutcome* a, const StartOutcome* b) {
    return a->information_collocation > b->information_collocation ||
           (a->information_collocation == b->information_collocation && a->index < b->index);
  });
  std::vector<LocalOptimum> out;
  for (const StartOutcome* s : converged) {
    const double v = s->information_collocation;
    if (!out.empty()) {
      const double b = out.back().information_collocation;
      if (std::abs(v - b) <= tolerance * std::max({1.0, std::abs(b), std::abs(v)})) {
        out.back().starts.push_back(s->index);
        continue;
      }
    }
    out.push_back({v, s->information_resimulated, s->objective, {s->index}});
  }
  return out;
}

std::optional<MultistartResult> run_multistart(const runtime::Model& model, const runtime::InputDesignProblem& d,
                                               const std::vector<DesignStart>& starts,
                                               const MultistartSettings& settings) {
  std::error_code ec;
  fs::create_directories(fs::path(settings.output_dir) / "starts", ec);
  Progress* progress = settings.run ? settings.run->progress : nullptr;
  std::size_t finished = 0;
  double best_so_far = nan;
  ParallelTasks tasks;
  tasks.count = starts.size();
  tasks.jobs = settings.jobs;
  tasks.log_dir = (fs::path(settings.output_dir) / "starts").string();
  tasks.solve = [&](std::size_t k, bool isolated) {
    if (!isolated && progress)
      progress->context(std::isfinite(best_so_far)
                            ? fmt::format("start {} of {}, best so far {:.6g}", k + 1, starts.size(), best_so_far)
                            : fmt::format("start {} of {}", k + 1, starts.size()));
    const auto began = std::chrono::steady_clock::now();
    const auto r = runtime::design_input(model, start_problem(d, starts[k], log_file(settings, k), isolated));
    return json{{"result", design_result_to_json(r)}, {"seconds", seconds_since(began)}};
  };
  tasks.done = [&](std::size_t, const json& j) {
    ++finished;
    if (j.contains("result")) {
      const auto& r = j.at("result").at("optimization");
      const double v = j.at("result").at("information_collocation").is_number()
                           ? j.at("result").at("information_collocation").get<double>()
                           : nan;
      const auto status = static_cast<runtime::OptimizationStatus>(r.at("status").get<int>());
      const bool ok = status == runtime::OptimizationStatus::success ||
                      status == runtime::OptimizationStatus::acceptable;
      if (ok && std::isfinite(v) && !(v <= best_so_far)) best_so_far = v;
    }
    if (progress && settings.jobs > 1)
      progress->context(fmt::format("{} of {} starts done ({} processes), best so far {:.6g}", finished,
                                    starts.size(), settings.jobs, best_so_far));
  };
  if (progress && settings.jobs > 1)
    progress->context(fmt::format("0 of {} starts done ({} processes)", starts.size(), settings.jobs));
  std::vector<json> results = run_parallel(tasks);
  if (results.empty()) return std::nullopt;  // an MPI rank other than 0
  MultistartResult m;
  bool have = false;  // m.best holds a result (the first one, until a better converged one)
  for (std::size_t k = 0; k < results.size(); ++k) {
    std::optional<runtime::InputDesignResult> r;
    if (results[k].contains("result")) r = design_result_from_json(results[k].at("result"));
    m.starts.push_back(outcome_of(k, starts[k], results[k], r ? &*r : nullptr));
    if (r && (!have || better(m.starts[k], &m.starts[m.best_start]))) {
      have = true;
      m.best = std::move(*r);
      m.best_start = k;
    }
    results[k] = json();  // free as we go
  }
  for (const auto& s : m.starts) m.best.start_information.push_back(s.converged ? s.information_collocation : nan);
  m.optima = cluster_optima(m.starts, settings.cluster_tol);
  fs::copy_file(log_file(settings, m.best_start), fs::path(settings.output_dir) / "ipopt.log",
                fs::copy_options::overwrite_existing, ec);  // absent when another machine solved it
  return m;
}

json multistart_json(const MultistartResult& m, const MultistartSettings& settings) {
  json starts = json::array();
  for (const auto& s : m.starts) {
    json j{{"start", s.index + 1}, {"origin", s.origin}, {"label", s.label}, {"status", s.status},
           {"iterations", s.iterations}, {"objective", number_json(s.objective)},
           {"information_collocation", number_json(s.information_collocation)},
           {"information_resimulated", number_json(s.information_resimulated)}, {"seconds", s.seconds}};
    if (!s.error.empty()) j["error"] = s.error;
    if (!s.hessian.empty()) j["hessian"] = s.hessian, j["attempts"] = s.attempts;
    starts.push_back(j);
  }
  json optima = json::array();
  for (const auto& o : m.optima) {
    json members = json::array();
    for (std::size_t k : o.starts) members.push_back(k + 1);
    optima.push_back({{"information_collocation", number_json(o.information_collocation)},
                      {"information_resimulated", number_json(o.information_resimulated)},
                      {"objective", number_json(o.objective)}, {"count", o.starts.size()},
                      {"starts", members}});
  }
  std::size_t converged = 0;
  for (const auto& s : m.starts) converged += s.converged ? 1 : 0;
  return {{"starts", m.starts.size()},
          {"converged", converged},
          {"best_start", m.optima.empty() && m.starts[m.best_start].status == "error" ? json(nullptr)
                                                                                   : json(m.best_start + 1)},
          {"reached_best", m.optima.empty() ? 0 : m.optima.front().starts.size()},
          {"cluster_tol", settings.cluster_tol},
          {"local_optima", optima},
          {"per_start", starts}};
}

void print_multistart(std::ostream& os, const MultistartResult& m, const std::string& criterion,
                      const MultistartSettings& settings) {
  std::size_t converged = 0;
  for (const auto& s : m.starts) converged += s.converged ? 1 : 0;
  os << fmt::format("morun: multistart: {} starts, {} converged, {} local optim{} (relative tolerance {:g}):\n",
                    m.starts.size(), converged, m.optima.size(), m.optima.size() == 1 ? "um" : "a",
                    settings.cluster_tol);
  for (std::size_t i = 0; i < m.optima.size(); ++i) {
    const LocalOptimum& o = m.optima[i];
    os << fmt::format("morun:   {}. {}-information {:.6g} (re-simulated {:.6g}), reached by {} start{} (first: {})\n",
                      i + 1, criterion, o.information_collocation, o.information_resimulated, o.starts.size(),
                      o.starts.size() == 1 ? "" : "s", m.starts[o.starts.front()].label);
  }
  for (const auto& s : m.starts)
    if (!s.converged)
      os << fmt::format("morun:   start {} ({}): {}{}\n", s.index + 1, s.label, s.status,
                        s.error.empty() ? "" : ": " + s.error);
  if (!m.optima.empty())
    os << fmt::format("morun: the best design (start {}) was reached by {} of {} starts\n", m.best_start + 1,
                      m.optima.front().starts.size(), m.starts.size());
}

}  // namespace mo::tools
