// Progress on stderr and per-phase timings for the command-line tools.
//
//   Progress      a status line ("morun: solve: iteration 42, objective ...,
//                 12.3 s") printed by a heartbeat thread once the current stage
//                 has run `delay` seconds, then at most once per `interval`;
//                 on a terminal one line redrawn in place, otherwise plain lines.
//   PhaseTimings  seconds per phase (flatten, lower, generate, compile, solve,
//                 simulate) for summary.json's `timings_seconds`.
#pragma once

#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <ostream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

namespace mo::tools {

/// Wall-clock seconds per phase of one tool run.
class PhaseTimings {
public:
  /// Adds `seconds` to `phase` (any name; the six standard ones always appear in json()).
  void add(const std::string& phase, double seconds);
  /// Seconds recorded for `phase` so far (0 if none).
  [[nodiscard]] double get(const std::string& phase) const;
  /// {"flatten", "lower", "generate", "compile", "solve", "simulate", other phases..., "total"}
  /// where total is the wall time since this object was made.
  [[nodiscard]] nlohmann::json json() const;

private:
  std::map<std::string, double> seconds_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// How progress is shown.
struct ProgressOptions {
  bool quiet = false;            ///< --quiet: show nothing
  bool terminal = false;         ///< redraw one line with '\r' (else one line per report)
  double delay_seconds = 2.0;    ///< a stage shorter than this shows nothing
  double interval_seconds = 1.0; ///< at most one report per interval
  std::string tool = "morun";    ///< line prefix
};

/// The options for stderr: terminal if stderr is a tty; MO_PROGRESS_SECONDS=S
/// (a positive number) sets both delay and interval to S (for tests and logs).
ProgressOptions stderr_progress_options(bool quiet, const std::string& tool);

/// A status line for long work, shown from a heartbeat thread. Thread-safe:
/// stage/detail may be called from any thread (e.g. a solver callback). In a
/// log (not a terminal) a stage that ran `delay` seconds has at least one line,
/// printed when it ends if the heartbeat was not scheduled in time.
class Progress {
public:
  /// Starts the heartbeat thread (none when quiet).
  Progress(std::ostream& out, ProgressOptions options);
  /// Ends the current stage and stops the heartbeat.
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Begins a stage (e.g. "compile"); its clock starts now; the detail is cleared.
  void stage(const std::string& name);
  /// The current state within the stage, e.g. "iteration 12, objective 3.1".
  void detail(const std::string& text);
  /// Shown before the detail until the stage ends, e.g. "start 2 of 3, best so far 41.2".
  void context(const std::string& text);
  /// Prints `line` (and a newline) to the stream, erasing a status line first.
  void println(const std::string& line);
  /// Ends the stage: nothing more is shown until the next stage() (on a
  /// terminal the status line is erased).
  void end_stage();

private:
  void heartbeat();
  void print_locked(std::chrono::steady_clock::time_point now);
  void finish_stage_locked();
  void erase_locked();

  std::ostream& out_;
  ProgressOptions options_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  bool active_ = false;
  bool line_shown_ = false;  // terminal: a status line is on screen
  bool stage_printed_ = false;  // the current stage has had a line
  std::string stage_, context_, detail_;
  std::chrono::steady_clock::time_point stage_start_, last_print_;
  std::thread thread_;
};

/// What a tool run shares with its stages: progress and timings. Either may be
/// used through a null pointer-free reference; `progress` is never null.
struct RunContext {
  Progress* progress = nullptr;  ///< the run's status line (never null when set by a tool)
  PhaseTimings timings;          ///< per-phase seconds
};

/// Times one phase: begins a progress stage named `phase` (with `detail`) and,
/// on destruction, ends it and adds the elapsed time to the phase. A null
/// context does nothing.
class PhaseScope {
public:
  PhaseScope(RunContext* run, std::string phase, const std::string& detail = {});
  ~PhaseScope();
  PhaseScope(const PhaseScope&) = delete;
  PhaseScope& operator=(const PhaseScope&) = delete;
  /// Seconds since the scope began.
  [[nodiscard]] double elapsed() const;

private:
  RunContext* run_;
  std::string phase_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// Seconds since `start`.
double seconds_since(std::chrono::steady_clock::time_point start);

/// Rewrites DIR/summary.json (atomically) with `timings_seconds` holding the
/// phases of `timings`, keeping keys already there that are not phases (e.g.
/// the runtime's nlp_build); the runtime's Ipopt time moves to "ipopt". Does
/// nothing if there is no summary.json; throws std::runtime_error on bad JSON.
void record_timings(const std::string& dir, const PhaseTimings& timings);

}  // namespace mo::tools
