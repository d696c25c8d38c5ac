// Running an external program (Scilab) with an argument vector, never a
// shell command line: its own process group, standard input from /dev/null,
// output to a log file, extra environment variables, a time limit, an early
// stop once the program has written a "done" file (Scilab can hang in exit
// after finishing its work), and one when its group stops using the CPU
// (Scilab's Java can hang at start-up, waiting on a lock).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace mo::tools {

/// What to run and how long to let it run.
struct ChildRun {
  std::vector<std::string> argv;  ///< argv[0] is the program's full path (no PATH lookup)
  std::vector<std::pair<std::string, std::string>> environment;  ///< set in the child (overriding)
  std::string log_file;           ///< stdout and stderr go here (truncated)
  std::string done_file;          ///< when it exists, the child is done: stop it after `grace_seconds`
  double timeout_seconds = 600.0; ///< then the whole process group is killed
  double grace_seconds = 5.0;
  /// If > 0: when no process of the group has used CPU time for this long
  /// (and no done file exists), the group is killed as stalled. Linux /proc.
  double stall_seconds = 0.0;
};

/// How the child ended.
enum class ChildOutcome {
  exited,        ///< it exited by itself (status in `exit_status`, -1 when killed by a signal)
  stopped_done,  ///< it wrote the done file and was stopped after the grace time
  timed_out,     ///< the time limit passed; it was killed
  stalled,       ///< its group used no CPU for `stall_seconds`; it was killed
  interrupted,   ///< this process got SIGINT, SIGTERM or SIGHUP; the child was killed
  not_started,   ///< fork or exec failed (`exit_status` 127)
};

struct ChildResult {
  ChildOutcome outcome = ChildOutcome::not_started;
  int exit_status = -1;
  double seconds = 0.0;  ///< wall time
};

/// Runs `run`, waits for it (polling every 100 ms) and reaps every process of
/// its group that it kills. While it waits, SIGINT, SIGTERM and SIGHUP stop
/// the child's group (which is not in the terminal's foreground group) and
/// return `interrupted`; the previous handlers are restored on return. Never
/// throws for the child's failures.
ChildResult run_child(const ChildRun& run);

}  // namespace mo::tools
