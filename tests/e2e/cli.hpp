// Running the command-line tools from tests: a scratch directory per test
// case under the build tree, morun with its compile cache in the build tree
// (tests never write to $HOME), exit status and stderr captured.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace mo::e2e {

namespace fs = std::filesystem;

inline const std::string kMorun = std::string(MO_BINARY_DIR) + "/tools/morun";

struct Run {
  int status = -1;
  std::string err;
};

inline std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline std::string quoted(const std::string& s) { return "'" + s + "'"; }

/// A fresh directory for one test case under the build tree.
inline fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(MO_BINARY_DIR) / "e2e-scratch" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// Runs morun with `args` (already quoted); its compile cache is kept in the
/// build tree so that tests never write to $HOME.
inline Run morun(const std::string& args, const fs::path& dir) {
  const fs::path err = dir / "stderr.txt";
  const std::string cmd = "XDG_CACHE_HOME=" + quoted(std::string(MO_TEST_CACHE_DIR) + "/morun-test-cache") + " " +
                          quoted(kMorun) + " " + args + " >/dev/null 2>" + quoted(err.string());
  const int raw = std::system(cmd.c_str());
  Run r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.err = slurp(err);
  return r;
}

}  // namespace mo::e2e
