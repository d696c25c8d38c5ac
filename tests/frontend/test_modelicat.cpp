// mocompile against Scilab's own flattener: each hierarchical circuit from
// Scilab's Electrical.mo / Hydraulics.mo, and our Coselica-style
// cart-pendulum, is flattened by modelicat (run here, when installed) and by
// mocompile; both results must have the same unknowns and equation count.
#include "compile.hpp"

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <set>

using namespace mo::test;
namespace fs = std::filesystem;

namespace {

/// modelicat writes array elements as `x.[1].[2]`; Modelica as `x[1,2]`.
std::string normalise(std::string n) {
  std::string out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    if (n.compare(i, 3, "].[") == 0) {
      out += ',';
      i += 2;
    } else if (n.compare(i, 2, ".[") == 0) {
      out += '[';
      i += 1;
    } else {
      out += n[i];
    }
  }
  return out;
}

std::set<std::string> unknowns(const mo::frontend::flat::Model &m) {
  std::set<std::string> s;
  for (const auto &v : m.variables)
    if (v.is_unknown()) s.insert(normalise(v.name));
  return s;
}

std::size_t equation_count(const mo::frontend::flat::Model &m) {
  std::size_t n = 0;
  for (const auto &e : m.equations) n += mo::frontend::flat::equation_count(e);
  return n;
}

/// Runs modelicat; returns the flat text, or "" (with a warning) when it is
/// not installed.
std::string run_modelicat(const std::vector<std::string> &libs, const std::string &cls) {
  std::string tool = MO_MODELICAT;
  if (tool.empty() || tool.find("NOTFOUND") != std::string::npos || !fs::exists(tool))
    return "";
  fs::path dir = fs::temp_directory_path() / ("mo_modelicat_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::path out = dir / (cls + "_flat.mo");
  std::string cmd = "'" + tool + "'";
  for (const auto &l : libs) cmd += " -lib '" + l + "'";
  cmd += " -o '" + out.string() + "' -command '" + cls + " " + cls + "_flat;' > '" + (dir / "log").string() + "' 2>&1";
  int status = std::system(cmd.c_str());
  std::string text = status == 0 ? read_file(out.string()) : "";
  fs::remove_all(dir);
  return text;
}

void compare(const std::vector<std::string> &libs, const std::string &cls, const std::string &committed_flat) {
  std::vector<Source> sources;
  for (const auto &l : libs) sources.push_back({l, read_file(l)});
  Compiled ours = compile(sources, cls);
  INFO(cls << ": " << ours.diagnostics);
  REQUIRE(ours.ok());
  std::string theirs_text = run_modelicat(libs, cls);
  if (theirs_text.empty()) {
    WARN("modelicat is not installed; comparing with the committed flat file " << committed_flat);
    theirs_text = read_file(committed_flat);
  }
  Compiled theirs = compile({{cls + "_flat.mo", theirs_text}});
  INFO("modelicat's output: " << theirs.diagnostics);
  REQUIRE(theirs.ok());
  CHECK(unknowns(*ours.model) == unknowns(*theirs.model));
  CHECK(equation_count(*ours.model) == equation_count(*theirs.model));
}

} // namespace

TEST_CASE("Scilab circuits: mocompile and modelicat agree", "[modelicat]") {
  int rows = 0;
  for (const auto &row : scilab_manifest()) {
    const std::string &file = row.file, &library = row.library, &cls = row.cls;
    std::string lib = std::string(MO_SCILAB_MACROS) + "/" + library + "/" + library + ".mo";
    std::string dir = std::string(MO_TEST_DATA_DIR) + "/scilab/";
    if (!fs::exists(lib)) {
      WARN("Scilab library " << lib << " missing (scripts/install-deps.sh)");
      continue;
    }
    std::string stem = file.substr(0, file.size() - 3);
    compare({lib, dir + file}, cls, dir + stem + ".flat.mo");
    ++rows;
  }
  CHECK(rows >= 8);
}

TEST_CASE("component cart-pendulum: mocompile and modelicat agree", "[modelicat]") {
  const std::string m = std::string(MO_SOURCE_DIR) + "/modelica/";
  compare({m + "MoLib.mo", m + "CartPendulum/CartPendulumComponents.mo"}, "CartPendulumComponents",
          m + "CartPendulum/CartPendulumComponents_flat.mo");
  compare({m + "MoLib.mo", m + "CartPendulum/CartPendulumComponents.mo"}, "CartPendulumComponentsSine",
          m + "CartPendulum/CartPendulumComponentsSine_flat.mo");
}
