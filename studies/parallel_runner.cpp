// Forked workers and MPI ranks for independent tasks; see parallel_runner.hpp.
#include "parallel_runner.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <thread>

#include "mpi_world.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace mo::tools {

namespace {

constexpr std::uint64_t kStop = ~std::uint64_t{0};

/// Writes all of `n` bytes; false on error.
bool write_all(int fd, const void* data, std::size_t n) {
  const char* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    p += w, n -= static_cast<std::size_t>(w);
  }
  return true;
}

/// Reads exactly `n` bytes; false on end of file or error.
bool read_all(int fd, void* data, std::size_t n) {
  char* p = static_cast<char*>(data);
  while (n > 0) {
    const ssize_t r = ::read(fd, p, n);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    p += r, n -= static_cast<std::size_t>(r);
  }
  return true;
}

json solve_caught(const ParallelTasks& t, std::size_t k, bool isolated) {
  try {
    return t.solve(k, isolated);
  } catch (const std::exception& e) {
    return json{{"error", e.what()}};
  }
}

/// One forked worker as the parent sees it.
struct Worker {
  pid_t pid = -1;
  int tasks = -1;    ///< parent writes task indices here
  int results = -1;  ///< parent reads results here
  std::size_t task = 0;
  bool busy = false;
};

/// The worker's life: task indices in, length-prefixed JSON out, until kStop.
[[noreturn]] void worker_loop(const ParallelTasks& t, int tasks, int results, const std::string& log) {
  const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (out >= 0) ::dup2(out, 1), ::dup2(out, 2), ::close(out);
  for (std::uint64_t k = 0; read_all(tasks, &k, sizeof k) && k != kStop;) {
    const std::string text = solve_caught(t, static_cast<std::size_t>(k), true).dump();
    const std::uint64_t n = text.size();
    if (!write_all(results, &n, sizeof n) || !write_all(results, text.data(), text.size())) break;
  }
  ::_exit(0);  // no destructors or atexit handlers of the parent's state
}

std::string worker_log(const ParallelTasks& t, std::size_t w) {
  if (t.log_dir.empty()) return "/dev/null";
  std::error_code ec;
  fs::create_directories(t.log_dir, ec);
  return (fs::path(t.log_dir) / fmt::format("worker_{}.log", w)).string();
}

/// Forks `n` workers; each child closes the parent's ends of every pipe.
std::vector<Worker> start_workers(const ParallelTasks& t, std::size_t n) {
  std::vector<Worker> workers;
  std::cout.flush(), std::cerr.flush(), std::fflush(nullptr);
  for (std::size_t w = 0; w < n; ++w) {
    int down[2], up[2];
    if (::pipe2(down, O_CLOEXEC) != 0) break;
    if (::pipe2(up, O_CLOEXEC) != 0) {
      ::close(down[0]), ::close(down[1]);
      break;
    }
    const std::string log = worker_log(t, w);
    const pid_t pid = ::fork();
    if (pid == 0) {
      for (const Worker& other : workers) ::close(other.tasks), ::close(other.results);
      ::close(down[1]), ::close(up[0]);
      worker_loop(t, down[0], up[1], log);
    }
    ::close(down[0]), ::close(up[1]);
    if (pid < 0) {
      ::close(down[1]), ::close(up[0]);
      break;
    }
    workers.push_back({pid, down[1], up[0], 0, false});
  }
  return workers;
}

std::string exit_text(pid_t pid) {
  int status = 0;
  if (::waitpid(pid, &status, 0) != pid) return "worker lost";
  if (WIFSIGNALED(status)) return fmt::format("worker process killed by signal {} ({})", WTERMSIG(status),
                                              ::strsignal(WTERMSIG(status)));
  return fmt::format("worker process exited with status {}", WEXITSTATUS(status));
}

/// Reads one result of a busy worker; on end of file the worker is reaped and
/// the task's result says why.
json receive(Worker& w) {
  std::uint64_t n = 0;
  std::string text;
  if (read_all(w.results, &n, sizeof n)) {
    text.resize(n);
    if (read_all(w.results, text.data(), n)) {
      json r = json::parse(text, nullptr, false);
      return r.is_discarded() ? json{{"error", "a worker returned malformed JSON"}} : r;
    }
  }
  ::close(w.tasks), ::close(w.results);
  w.tasks = w.results = -1;
  const std::string why = exit_text(w.pid);
  w.pid = -1;
  return json{{"error", why + " while solving this task"}};
}

bool dispatch(Worker& w, std::uint64_t k) {
  if (!write_all(w.tasks, &k, sizeof k)) return false;
  w.task = static_cast<std::size_t>(k), w.busy = true;
  return true;
}

void stop_workers(std::vector<Worker>& workers) {
  for (Worker& w : workers) {
    if (w.pid < 0) continue;
    write_all(w.tasks, &kStop, sizeof kStop);
    ::close(w.tasks), ::close(w.results);
    int status = 0;
    ::waitpid(w.pid, &status, 0);
  }
}

/// The local tasks on forked workers, handed out as workers become free.
void run_forked(const ParallelTasks& t, const std::vector<std::size_t>& local, std::vector<json>& out) {
  // A write to a worker that died fails with EPIPE instead of killing morun
  // (and a worker whose parent died stops the same way).
  struct IgnoreSigpipe {
    struct sigaction old {};
    IgnoreSigpipe() {
      struct sigaction ignore {};
      ignore.sa_handler = SIG_IGN;
      ::sigaction(SIGPIPE, &ignore, &old);
    }
    ~IgnoreSigpipe() { ::sigaction(SIGPIPE, &old, nullptr); }
  } sigpipe;
  std::vector<Worker> workers = start_workers(t, std::min<std::size_t>(t.jobs, local.size()));
  std::size_t next = 0, pending = 0;
  auto feed = [&](Worker& w) {
    while (next < local.size() && w.pid >= 0 && !w.busy) {
      if (dispatch(w, local[next])) ++next, ++pending;
      else break;
    }
  };
  for (Worker& w : workers) feed(w);
  while (pending > 0) {
    std::vector<pollfd> fds;
    std::vector<Worker*> owners;
    for (Worker& w : workers)
      if (w.busy) fds.push_back({w.results, POLLIN, 0}), owners.push_back(&w);
    if (::poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (std::size_t i = 0; i < fds.size(); ++i) {
      if (fds[i].revents == 0) continue;
      Worker& w = *owners[i];
      out[w.task] = receive(w);
      w.busy = false, --pending;
      if (t.done) t.done(w.task, out[w.task]);
      feed(w);
    }
  }
  for (; next < local.size(); ++next) {  // every worker failed to start or died
    out[local[next]] = solve_caught(t, local[next], false);
    if (t.done) t.done(local[next], out[local[next]]);
  }
  stop_workers(workers);
  for (std::size_t w = 0; w < workers.size() && !t.log_dir.empty(); ++w) {  // keep only logs with something
    std::error_code ec;
    const fs::path log = worker_log(t, w);
    if (fs::file_size(log, ec) == 0 && !ec) fs::remove(log, ec);
  }
}

/// Rank 0 collects the other ranks' results (every rank calls this).
void gather_ranks(const std::vector<std::size_t>& local, std::vector<json>& out) {
  json mine = json::object();
  for (std::size_t k : local) mine[std::to_string(k)] = std::move(out[k]);
  const std::vector<std::string> all = mpi_gather(mine.dump());
  if (!mpi_world().root()) {
    out.clear();
    return;
  }
  for (const std::string& text : all) {
    const json results = json::parse(text);  // named: items() does not keep a temporary alive
    for (const auto& [key, value] : results.items()) out[std::stoul(key)] = value;
  }
}

}  // namespace

unsigned default_jobs() { return std::max(1u, std::thread::hardware_concurrency()); }

std::vector<json> run_parallel(const ParallelTasks& t) {
  const MpiWorld& world = mpi_world();
  std::vector<json> out(t.count);
  std::vector<std::size_t> local;
  for (std::size_t k = 0; k < t.count; ++k)
    if (k % static_cast<std::size_t>(world.size) == static_cast<std::size_t>(world.rank)) local.push_back(k);
  if (world.size == 1 && t.jobs > 1 && local.size() > 1) {
    run_forked(t, local, out);
  } else {
    for (std::size_t k : local) {
      out[k] = solve_caught(t, k, false);
      if (t.done) t.done(k, out[k]);
    }
  }
  if (world.size > 1) gather_ranks(local, out);
  return out;
}

}  // namespace mo::tools
