// Running mocompile and morun on Xcos diagrams from tests (issue 14): the
// tools with their arguments and extra environment, stderr captured, the
// compile cache in the build tree; and whether Scilab is installed.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "e2e/cli.hpp"

namespace mo::e2e {

inline const std::string kMocompile = std::string(MO_BINARY_DIR) + "/tools/mocompile";

/// Runs `tool` in DIR with `args` (each quoted here) and `env` ("NAME=value",
/// each quoted) in the environment; stdout to DIR/stdout.txt, stderr captured.
inline Run run_tool(const std::string& tool, const std::vector<std::string>& args, const fs::path& dir,
                    const std::vector<std::string>& env = {}) {
  std::string cmd = "cd " + quoted(dir.string()) + " && env XDG_CACHE_HOME=" + quoted(std::string(MO_TEST_CACHE_DIR) + "/morun-test-cache");
  for (const auto& e : env) cmd += " " + quoted(e);
  cmd += " " + quoted(tool);
  for (const auto& a : args) cmd += " " + quoted(a);
  cmd += " >" + quoted((dir / "stdout.txt").string()) + " 2>" + quoted((dir / "stderr.txt").string());
  const int raw = std::system(cmd.c_str());
  Run r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.err = slurp(dir / "stderr.txt");
  return r;
}

/// True when a Scilab that can read diagrams is installed (scilab and
/// xvfb-run on PATH, or MO_SCILAB set).
inline bool scilab_installed() {
  return std::system("command -v xvfb-run >/dev/null 2>&1 && "
                     "{ [ -n \"${MO_SCILAB:-}\" ] || command -v scilab >/dev/null 2>&1; }") == 0;
}

/// The input names listed in the tool's note on a diagram's free inputs.
inline std::vector<std::string> noted_inputs(const std::string& err) {
  std::vector<std::string> names;
  const auto note = err.find("non-Modelica blocks drive the model through");
  if (note == std::string::npos) return names;
  const auto end = err.find('\n', note);
  for (auto q = err.find('\'', note); q != std::string::npos && q < end;) {
    const auto close = err.find('\'', q + 1);
    if (close == std::string::npos) break;
    names.push_back(err.substr(q + 1, close - q - 1));
    q = err.find('\'', close + 1);
  }
  return names;
}

}  // namespace mo::e2e
