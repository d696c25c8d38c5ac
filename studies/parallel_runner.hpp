// Independent tasks (the starts of a design, the runs of a Monte-Carlo study)
// solved concurrently: on this machine by forked worker processes, across
// machines by MPI ranks (mpi_world.hpp).
//
// Processes, not threads: Debian's Ipopt uses MUMPS' sequential build, whose
// state is global (not thread-safe), and a forked worker inherits the loaded
// model and everything built before the fork. Each worker takes task indices
// from the parent through a pipe as it becomes free (so uneven solve times
// balance) and returns each result as one JSON document (doubles round-trip
// exactly, so a result does not depend on which process solved it). Workers
// write nothing to the terminal: their stdout and stderr go to a log file (or
// /dev/null) and they end with _exit, so the parent's progress line is never
// interleaved with their output.
//
// Under `mpirun -n K`, rank r takes the tasks k with k mod K = r and solves
// them in turn (one rank per core is mpirun's business); rank 0 gathers every
// result.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace mo::tools {

/// What run_parallel() solves.
struct ParallelTasks {
  std::size_t count = 0;  ///< tasks 0 .. count-1
  /// Worker processes on this machine; 1 (or a single local task) solves in
  /// this process. Ignored under MPI with several ranks (each solves in turn).
  unsigned jobs = 1;
  /// Solves task k. `isolated` is true in a forked worker: it must not touch
  /// the caller's progress line or print. An exception becomes {"error": what}.
  std::function<nlohmann::json(std::size_t k, bool isolated)> solve;
  /// Called in this process when a task of this rank finishes (in completion
  /// order), e.g. for progress; may be empty.
  std::function<void(std::size_t k, const nlohmann::json& result)> done;
  /// Workers' stdout and stderr go to LOG_DIR/worker_<w>.log; empty: /dev/null.
  std::string log_dir;
};

/// Solves every task; returns the results by task index. On MPI rank 0 (and
/// without MPI) every entry is filled; on the other ranks the result is empty.
/// A task whose worker died holds {"error": "..."}.
std::vector<nlohmann::json> run_parallel(const ParallelTasks& tasks);

/// The default number of local jobs: the number of cores (at least 1).
unsigned default_jobs();

}  // namespace mo::tools
