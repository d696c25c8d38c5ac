// Progress lines and phase timings; see progress.hpp.
#include "progress.hpp"

#include <unistd.h>

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "mo/runtime/result.hpp"

namespace mo::tools {

namespace {

using Clock = std::chrono::steady_clock;

const char* const kPhases[] = {"flatten", "lower", "generate", "compile", "solve", "simulate"};

}  // namespace

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void PhaseTimings::add(const std::string& phase, double seconds) { seconds_[phase] += seconds; }

double PhaseTimings::get(const std::string& phase) const {
  const auto it = seconds_.find(phase);
  return it == seconds_.end() ? 0.0 : it->second;
}

nlohmann::json PhaseTimings::json() const {
  nlohmann::json j = nlohmann::json::object();
  for (const char* phase : kPhases) j[phase] = get(phase);
  for (const auto& [phase, s] : seconds_) j[phase] = s;
  j["total"] = seconds_since(start_);
  return j;
}

void record_timings(const std::string& dir, const PhaseTimings& timings) {
  const std::string path = (std::filesystem::path(dir) / "summary.json").string();
  std::ifstream in(path);
  if (!in) return;
  nlohmann::json summary = nlohmann::json::parse(in, nullptr, false);
  if (summary.is_discarded() || !summary.is_object())
    throw std::runtime_error(path + ": not a JSON object, cannot add timings");
  nlohmann::json merged = nlohmann::json::object();
  if (auto it = summary.find("timings_seconds"); it != summary.end() && it->is_object()) {
    merged = *it;
    if (merged.contains("solve")) merged["ipopt"] = merged["solve"];
  }
  const nlohmann::json phases = timings.json();
  for (const auto& [key, value] : phases.items()) merged[key] = value;
  summary["timings_seconds"] = merged;
  runtime::write_file_atomic(path, [&](std::ostream& os) { os << summary.dump(2) << "\n"; });
}

ProgressOptions stderr_progress_options(bool quiet, const std::string& tool) {
  ProgressOptions o;
  o.quiet = quiet;
  o.tool = tool;
  o.terminal = ::isatty(STDERR_FILENO) != 0;
  if (!o.terminal) o.interval_seconds = 10.0;  // a log file gets a line every 10 s
  if (const char* env = std::getenv("MO_PROGRESS_SECONDS")) {
    char* end = nullptr;
    const double s = std::strtod(env, &end);
    if (end != env && *end == '\0' && s > 0) o.delay_seconds = o.interval_seconds = s;
  }
  return o;
}

Progress::Progress(std::ostream& out, ProgressOptions options) : out_(out), options_(std::move(options)) {
  if (!options_.quiet) thread_ = std::thread([this] { heartbeat(); });
}

Progress::~Progress() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    erase_locked();
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void Progress::stage(const std::string& name) {
  std::lock_guard lock(mutex_);
  finish_stage_locked();
  erase_locked();
  stage_ = name;
  stage_printed_ = false;
  detail_.clear();
  context_.clear();
  active_ = true;
  stage_start_ = Clock::now();
}

void Progress::detail(const std::string& text) {
  std::lock_guard lock(mutex_);
  detail_ = text;
}

void Progress::context(const std::string& text) {
  std::lock_guard lock(mutex_);
  context_ = text;
}

void Progress::println(const std::string& line) {
  std::lock_guard lock(mutex_);
  erase_locked();
  out_ << line << "\n" << std::flush;
}

void Progress::end_stage() {
  std::lock_guard lock(mutex_);
  finish_stage_locked();
  erase_locked();
  active_ = false;
}

void Progress::finish_stage_locked() {
  if (!active_ || stage_printed_ || options_.quiet || options_.terminal) return;
  const auto now = Clock::now();
  if (std::chrono::duration<double>(now - stage_start_).count() >= options_.delay_seconds) print_locked(now);
}

void Progress::heartbeat() {
  const auto tick = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(std::min(0.25, options_.interval_seconds / 2)));
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, tick);
    if (stopping_ || !active_) continue;
    const auto now = Clock::now();
    const double running = std::chrono::duration<double>(now - stage_start_).count();
    const double since = std::chrono::duration<double>(now - last_print_).count();
    if (running >= options_.delay_seconds && since >= options_.interval_seconds) print_locked(now);
  }
}

void Progress::print_locked(Clock::time_point now) {
  const double running = std::chrono::duration<double>(now - stage_start_).count();
  std::string line = fmt::format("{}: {}: ", options_.tool, stage_);
  for (const std::string* part : {&context_, &detail_})
    if (!part->empty()) line += *part + "; ";
  line += fmt::format("{:.0f} s", running);
  if (options_.terminal) {
    line = "\r\033[K" + line;  // redraw in place
    line_shown_ = true;
  } else {
    line += "\n";
  }
  out_ << line << std::flush;
  last_print_ = now;
  stage_printed_ = true;
}

void Progress::erase_locked() {
  if (!line_shown_) return;
  out_ << "\r\033[K" << std::flush;
  line_shown_ = false;
}

PhaseScope::PhaseScope(RunContext* run, std::string phase, const std::string& detail)
    : run_(run), phase_(std::move(phase)) {
  if (!run_ || !run_->progress) return;
  run_->progress->stage(phase_);
  if (!detail.empty()) run_->progress->detail(detail);
}

PhaseScope::~PhaseScope() {
  if (!run_) return;
  run_->timings.add(phase_, elapsed());
  if (run_->progress) run_->progress->end_stage();
}

double PhaseScope::elapsed() const { return seconds_since(start_); }

}  // namespace mo::tools
