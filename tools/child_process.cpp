#include "child_process.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <iterator>
#include <cstdio>
#include <cstring>
#include <optional>
#include <thread>

extern char** environ;

namespace mo::tools {

namespace {

using Clock = std::chrono::steady_clock;

volatile std::sig_atomic_t g_signal = 0;  // set by on_signal while run_child waits

extern "C" void on_signal(int signal) { g_signal = signal; }

/// Routes SIGINT, SIGTERM and SIGHUP to on_signal for its lifetime.
class SignalGuard {
public:
  SignalGuard() {
    g_signal = 0;
    struct sigaction action {};
    action.sa_handler = on_signal;
    sigemptyset(&action.sa_mask);
    for (std::size_t i = 0; i < std::size(kSignals); ++i) ::sigaction(kSignals[i], &action, &previous_[i]);
  }
  ~SignalGuard() {
    for (std::size_t i = 0; i < std::size(kSignals); ++i) ::sigaction(kSignals[i], &previous_[i], nullptr);
  }
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;

private:
  static constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
  struct sigaction previous_[std::size(kSignals)] {};
};

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// The parent's environment with `overrides` replacing or adding entries, as
/// "NAME=value" strings (built before fork: the child only calls exec).
std::vector<std::string> child_environment(const std::vector<std::pair<std::string, std::string>>& overrides) {
  std::vector<std::string> out;
  for (char** e = environ; e && *e; ++e) {
    const std::string entry = *e;
    bool replaced = false;
    for (const auto& [name, value] : overrides)
      if (entry.compare(0, name.size() + 1, name + "=") == 0) replaced = true;
    if (!replaced) out.push_back(entry);
  }
  for (const auto& [name, value] : overrides) out.push_back(name + "=" + value);
  return out;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> out;
  for (auto& s : strings) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

/// In the child: own process group, stdin from /dev/null, output to the log, exec.
[[noreturn]] void exec_child(char* const* argv, char* const* envp, const char* log_file) {
  ::setpgid(0, 0);
  const int in = ::open("/dev/null", O_RDONLY);
  if (in >= 0) ::dup2(in, 0);
  const int log = ::open(log_file, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (log >= 0) {
    ::dup2(log, 1);
    ::dup2(log, 2);
  }
  ::execve(argv[0], argv, envp);
  static const char message[] = "cannot execute the program\n";
  [[maybe_unused]] auto unused = ::write(2, message, sizeof message - 1);
  ::_exit(127);
}

/// CPU time (clock ticks, user and system, with reaped children) of every
/// process whose group is `group`, from /proc/PID/stat.
long long group_cpu_ticks(pid_t group) {
  long long total = 0;
  DIR* dir = ::opendir("/proc");
  if (!dir) return -1;
  while (const dirent* entry = ::readdir(dir)) {
    if (entry->d_name[0] < '0' || entry->d_name[0] > '9') continue;
    const std::string path = std::string("/proc/") + entry->d_name + "/stat";
    std::FILE* f = std::fopen(path.c_str(), "r");
    if (!f) continue;  // the process has gone
    char line[1024];
    const bool read = std::fgets(line, sizeof line, f) != nullptr;
    std::fclose(f);
    const char* after = read ? std::strrchr(line, ')') : nullptr;  // the name may hold spaces
    if (!after) continue;
    // After the name: state ppid pgrp session tty tpgid flags minflt cminflt
    // majflt cmajflt utime stime cutime cstime (fields 3 to 17).
    char state = 0;
    long long ppid = 0, pgrp = 0, skip = 0, utime = 0, stime = 0, cutime = 0, cstime = 0;
    if (std::sscanf(after + 1, " %c %lld %lld %lld %lld %lld %lld %lld %lld %lld %lld %lld %lld %lld %lld", &state,
                    &ppid, &pgrp, &skip, &skip, &skip, &skip, &skip, &skip, &skip, &skip, &utime, &stime, &cutime,
                    &cstime) != 15)
      continue;
    if (pgrp == group) total += utime + stime + cutime + cstime;
  }
  ::closedir(dir);
  return total;
}

bool exists(const std::string& path) {
  struct stat st {};
  return !path.empty() && ::stat(path.c_str(), &st) == 0;
}

/// SIGTERM to the group, SIGKILL after 2 s if the leader has not exited; reaps it.
void stop_group(pid_t pid) {
  ::kill(-pid, SIGTERM);
  const auto start = Clock::now();
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (seconds_since(start) > 2.0) {
      ::kill(-pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ::kill(-pid, SIGKILL);  // whatever of the group outlived its leader (Xvfb, Java)
}

}  // namespace

ChildResult run_child(const ChildRun& run) {
  ChildResult result;
  if (run.argv.empty()) return result;
  std::vector<std::string> args = run.argv;
  std::vector<std::string> env = child_environment(run.environment);
  std::vector<char*> argv = pointers(args);
  std::vector<char*> envp = pointers(env);
  const auto start = Clock::now();
  SignalGuard signals;
  const pid_t pid = ::fork();
  if (pid < 0) {
    result.exit_status = 127;
    return result;
  }
  if (pid == 0) exec_child(argv.data(), envp.data(), run.log_file.c_str());
  ::setpgid(pid, pid);  // also from the parent, so that kill(-pid) works at once
  std::optional<Clock::time_point> done_at;
  long long cpu = -1;  // the group's CPU ticks when last seen to change
  auto cpu_changed = Clock::now(), cpu_checked = Clock::now();
  for (;;) {
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      ::kill(-pid, SIGKILL);  // leftovers of its group
      result.outcome = ChildOutcome::exited;
      result.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      if (result.exit_status == 127) result.outcome = ChildOutcome::not_started;
      break;
    }
    if (!done_at && exists(run.done_file)) done_at = Clock::now();
    if (done_at && seconds_since(*done_at) > run.grace_seconds) {
      stop_group(pid);
      result.outcome = ChildOutcome::stopped_done;
      break;
    }
    if (g_signal != 0) {
      stop_group(pid);
      result.outcome = ChildOutcome::interrupted;
      break;
    }
    if (seconds_since(start) > run.timeout_seconds) {
      stop_group(pid);
      result.outcome = ChildOutcome::timed_out;
      break;
    }
    if (run.stall_seconds > 0 && !done_at && seconds_since(cpu_checked) >= 1.0) {
      cpu_checked = Clock::now();
      if (const long long now = group_cpu_ticks(pid); now != cpu) {
        cpu = now;
        cpu_changed = cpu_checked;
      } else if (seconds_since(cpu_changed) > run.stall_seconds) {
        stop_group(pid);
        result.outcome = ChildOutcome::stalled;
        break;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace mo::tools
