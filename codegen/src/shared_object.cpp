// Compile cache and dlopen; see shared_object.hpp.
#include "mo/codegen/shared_object.hpp"

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <sstream>
#include <system_error>

namespace mo::codegen {

namespace fs = std::filesystem;

namespace {

/// FNV-1a, 64 bits, continued from `h`.
std::uint64_t fnv1a(std::string_view bytes, std::uint64_t h) {
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

std::string read_file(const fs::path& p) {
  std::ifstream is(p, std::ios::binary);
  std::ostringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

/// The cache key: two FNV-1a hashes with different seeds over everything
/// that can change the shared object, 128 bits as hex.
std::string cache_key(const GeneratedSources& s, const CompilerOptions& o) {
  std::string all = "mocompile-codegen-1\n" + o.compiler + "\n";
  for (const auto& f : o.flags) all += f + "\n";
  for (const auto& f : o.link_flags) all += f + "\n";
  for (const auto& d : o.include_dirs) {
    all += d + "\n";
    for (const char* h : {"mo/runtime/model.hpp", "mo/runtime/generated_support.hpp", "mo/runtime/modelica_random.hpp",
                          "mo/runtime/delay_lines.hpp"})
      if (fs::exists(fs::path(d) / h)) all += read_file(fs::path(d) / h);
  }
  for (const auto& f : s.files) all += f.path + "\n" + std::to_string(f.text.size()) + "\n" + f.text;
  return fmt::format("{:016x}{:016x}", fnv1a(all, 0xcbf29ce484222325ull),
                     fnv1a(all, 0x84222325cbf29ce4ull));
}

struct Job {
  std::vector<std::string> argv;
  fs::path log;
};

pid_t spawn(const Job& job) {
  const pid_t pid = ::fork();
  if (pid < 0) throw std::system_error(errno, std::generic_category(), "fork");
  if (pid == 0) {
    const int fd = ::open(job.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::close(fd);
    }
    std::vector<char*> args;
    for (const auto& a : job.argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  return pid;
}

std::string command_line(const Job& job) {
  std::string out;
  for (const auto& a : job.argv) out += (out.empty() ? "" : " ") + a;
  return out;
}

[[noreturn]] void compile_failed(const Job& job, int status) {
  std::string log = read_file(job.log);
  if (log.size() > 8000) log = log.substr(0, 8000) + "\n[... compiler output truncated]";
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127 && log.empty())
    log = "cannot run the compiler (not found on PATH?)";
  throw CompileError(fmt::format("compiling the generated model failed:\n  {}\n{}",
                                 command_line(job), log));
}

/// Runs the jobs, at most `parallel` at a time; throws at the first failure.
void run_jobs(const std::vector<Job>& jobs, unsigned parallel) {
  std::vector<std::pair<pid_t, std::size_t>> running;
  std::size_t next = 0;
  auto wait_one = [&] {
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    for (std::size_t i = 0; i < running.size(); ++i) {
      if (running[i].first != pid) continue;
      const std::size_t job = running[i].second;
      running.erase(running.begin() + static_cast<std::ptrdiff_t>(i));
      if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        for (auto [other, unused] : running) ::waitpid(other, nullptr, 0);
        compile_failed(jobs[job], status);
      }
      return;
    }
  };
  while (next < jobs.size() || !running.empty()) {
    if (next < jobs.size() && running.size() < std::max(1u, parallel)) {
      running.emplace_back(spawn(jobs[next]), next);
      ++next;
    } else {
      wait_one();
    }
  }
}

}  // namespace

std::string default_cache_dir() {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/mocompile";
  if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.cache/mocompile";
  return "/tmp/mocompile-cache";
}

CompiledModel compile_shared_object(const GeneratedSources& sources, const CompilerOptions& o) {
  CompiledModel out;
  out.key = cache_key(sources, o);
  const fs::path root = o.cache_dir.empty() ? fs::path(default_cache_dir()) : fs::path(o.cache_dir);
  const fs::path dir = root / out.key;
  out.library = (dir / "model.so").string();
  if (fs::exists(out.library)) {
    out.cached = true;
    return out;
  }
  const auto start = std::chrono::steady_clock::now();
  fs::create_directories(root);
  const fs::path temp = root / fmt::format("{}.tmp{}", out.key, ::getpid());
  fs::remove_all(temp);
  write_sources(sources, temp.string());
  std::vector<std::string> base{o.compiler};
  base.insert(base.end(), o.flags.begin(), o.flags.end());
  for (const auto& d : o.include_dirs) base.push_back("-I" + d);
  base.push_back("-I" + temp.string());
  std::vector<Job> compile;
  std::vector<std::string> objects;
  for (const auto& src : sources.sources()) {
    Job job{base, temp / (src + ".log")};
    objects.push_back((temp / (src + ".o")).string());
    job.argv.insert(job.argv.end(), {"-c", (temp / src).string(), "-o", objects.back()});
    compile.push_back(std::move(job));
  }
  run_jobs(compile, o.jobs);
  Job link{{o.compiler}, temp / "link.log"};
  link.argv.insert(link.argv.end(), o.flags.begin(), o.flags.end());
  link.argv.push_back("-shared");
  link.argv.insert(link.argv.end(), objects.begin(), objects.end());
  link.argv.insert(link.argv.end(), o.link_flags.begin(), o.link_flags.end());
  link.argv.insert(link.argv.end(), {"-o", (temp / "model.so").string()});
  run_jobs({link}, 1);
  for (const auto& obj : objects) fs::remove(obj);
  std::error_code ec;
  fs::rename(temp, dir, ec);
  if (ec) {  // another process finished the same key first: use its library
    fs::remove_all(temp);
    if (!fs::exists(out.library)) throw std::system_error(ec, "cannot move " + temp.string());
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

LoadedModel::LoadedModel(const std::string& library, const std::string& factory_symbol) {
  void* handle = ::dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) throw std::runtime_error(std::string("cannot load model: ") + ::dlerror());
  void* symbol = ::dlsym(handle, factory_symbol.c_str());
  if (!symbol)
    throw std::runtime_error("cannot load model: " + library + " has no " + factory_symbol);
  factory_ = reinterpret_cast<runtime::Model* (*)()>(symbol);
}

std::unique_ptr<runtime::Model> LoadedModel::create() const {
  return std::unique_ptr<runtime::Model>(factory_());
}

CompilerOptions runtime_compiler_options() {
  CompilerOptions o;
  // An installed tree: <prefix>/bin/tool, headers in <prefix>/include, library in <prefix>/lib.
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path prefix = exe.parent_path().parent_path();
  fs::path include = MO_RUNTIME_INCLUDE_DIR;
  if (!ec && fs::exists(prefix / "include/mo/runtime/model.hpp")) include = prefix / "include";
  o.include_dirs = {include.string(), MO_EIGEN_INCLUDE_DIR};
  // No -lmo_runtime: the model's runtime symbols resolve at dlopen() against
  // the runtime the loading process already holds (runtime/README.md), so the
  // key does not depend on where that library was built and two builds of one
  // tree (release and sanitized) share compiled models.
  return o;
}

}  // namespace mo::codegen
