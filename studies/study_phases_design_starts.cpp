// Multistart of the multi-phase design; see study_phases_internal.hpp.
//
// Each start simulates its own guess, so each has its own mode sequence,
// phases and stacked model (compiled in its worker; the compile cache is
// shared and safe between processes). A worker returns its run as one JSON
// document: the design result (design_result_json.hpp), the event status and
// summary, or why the start gave no result.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>

#include "design_result_json.hpp"
#include "parallel_runner.hpp"
#include "study_phases_internal.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace mo::tools {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

bool converged(const std::string& status, double information) {
  return (status == "success" || status == "acceptable") && std::isfinite(information);
}

json run_to_json(const EventDesignRun& r, double seconds) {
  json j{{"seconds", seconds}};
  if (r.refusal) {
    j["error"] = r.refusal->message + " (refused by the multi-phase collocation)";
  } else if (!r.error.empty()) {
    j["error"] = r.error;
  } else {
    j["result"] = design_result_to_json(r.result);
    j["status"] = r.status;
    j["events"] = r.events;
  }
  return j;
}

StartOutcome outcome_of(std::size_t k, const DesignStart& start, const json& j) {
  StartOutcome o{k, start.origin, start.label, "error", false, 0, nan, nan, nan, j.value("seconds", 0.0), "", "", 0};
  if (!j.contains("result")) {
    o.error = j.value("error", std::string("no result"));
    return o;
  }
  const json& r = j.at("result");
  auto number = [&](const char* key) { return r.at(key).is_number() ? r.at(key).get<double>() : nan; };
  o.status = j.at("status").get<std::string>();
  o.information_collocation = number("information_collocation");
  o.information_resimulated = number("information_resimulated");
  o.converged = converged(o.status, o.information_collocation);
  const json& opt = r.at("optimization");
  o.iterations = opt.at("iterations").get<int>();
  o.objective = opt.at("objective").is_number() ? opt.at("objective").get<double>() : nan;
  return o;
}

std::string log_file(const MultistartSettings& s, std::size_t k) {
  return (fs::path(s.output_dir) / "starts" / fmt::format("ipopt_{}.log", k + 1)).string();
}

}  // namespace

std::optional<MultistartResult> event_design_multistart(
    const std::vector<DesignStart>& starts, const MultistartSettings& settings,
    const std::function<EventDesignRun(std::size_t k, const std::string& log_file, bool isolated)>& solve,
    EventDesignRun& best) {
  std::error_code ec;
  fs::create_directories(fs::path(settings.output_dir) / "starts", ec);
  Progress* progress = settings.run ? settings.run->progress : nullptr;
  std::size_t finished = 0;
  ParallelTasks tasks;
  tasks.count = starts.size();
  tasks.jobs = settings.jobs;
  tasks.log_dir = (fs::path(settings.output_dir) / "starts").string();
  tasks.solve = [&](std::size_t k, bool isolated) {
    if (!isolated && progress) progress->context(fmt::format("start {} of {}", k + 1, starts.size()));
    const auto began = std::chrono::steady_clock::now();
    const EventDesignRun r = solve(k, log_file(settings, k), isolated);
    return run_to_json(r, std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count());
  };
  tasks.done = [&](std::size_t, const json&) {
    ++finished;
    if (progress && settings.jobs > 1)
      progress->context(fmt::format("{} of {} starts done ({} processes)", finished, starts.size(), settings.jobs));
  };
  std::vector<json> results = run_parallel(tasks);
  if (results.empty()) return std::nullopt;  // an MPI rank other than 0
  MultistartResult m;
  std::optional<std::size_t> chosen;
  for (std::size_t k = 0; k < results.size(); ++k) {
    m.starts.push_back(outcome_of(k, starts[k], results[k]));
    const StartOutcome& o = m.starts.back();
    const bool has_result = results[k].contains("result");
    const bool better = o.converged && (!chosen || !m.starts[*chosen].converged ||
                                        o.information_collocation > m.starts[*chosen].information_collocation);
    if (has_result && (!chosen || better)) chosen = k;
  }
  if (!chosen) {  // the table of starts says why each failed
    best.error = fmt::format("no start of the design gave a result (start 1: {})", m.starts[0].error);
    return m;
  }
  const json& j = results[*chosen];
  best.result = design_result_from_json(j.at("result"));
  best.status = j.at("status").get<std::string>();
  best.events = j.at("events");
  m.best_start = *chosen;
  for (const auto& o : m.starts) best.result.start_information.push_back(o.converged ? o.information_collocation : nan);
  m.best = best.result;
  m.optima = cluster_optima(m.starts, settings.cluster_tol);
  fs::copy_file(log_file(settings, m.best_start), fs::path(settings.output_dir) / "ipopt.log",
                fs::copy_options::overwrite_existing, ec);  // absent when another machine solved it
  return m;
}

}  // namespace mo::tools
