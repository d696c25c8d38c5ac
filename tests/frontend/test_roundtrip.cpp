// Flat output is flat Modelica: printing, parsing and flattening it again
// gives the same text (for Xcos flat files and for flattened hierarchies).
#include "compile.hpp"

#include <catch2/catch.hpp>

using namespace mo::test;

namespace {

void check_round_trip(const Compiled &first, const std::string &what) {
  INFO(what << "\n" << first.diagnostics);
  REQUIRE(first.ok());
  std::string once = first.model->print();
  Compiled again = compile({{"roundtrip.mo", once}}, first.model->name);
  INFO("reprinted:\n" << once << "\n" << again.diagnostics);
  REQUIRE(again.ok());
  CHECK(again.model->print() == once);
  CHECK(again.model->variables.size() == first.model->variables.size());
  CHECK(again.model->equations.size() == first.model->equations.size());
}

} // namespace

TEST_CASE("Xcos flat files print back to flat Modelica that flattens to the same text", "[roundtrip]") {
  auto files = list_files(std::string(MO_TEST_DATA_DIR) + "/scilab", ".flat.mo");
  for (auto &f : list_files(std::string(MO_SOURCE_DIR) + "/modelica/CartPendulum", "_flat.mo"))
    files.push_back(f);
  REQUIRE(files.size() >= 10);
  for (const auto &f : files)
    check_round_trip(compile({{f, read_file(f)}}), f);
}

TEST_CASE("flattened hierarchical models round-trip", "[roundtrip]") {
  const std::string macros = MO_SCILAB_MACROS;
  const std::string lib_dir = std::string(MO_TEST_DATA_DIR) + "/scilab/";
  for (const auto &row : scilab_manifest()) {
    std::string lib = macros + "/" + row.library + "/" + row.library + ".mo";
    if (read_file(lib).empty()) {
      WARN("Scilab library " << lib << " is not installed (scripts/install-deps.sh)");
      continue;
    }
    check_round_trip(compile({{lib, read_file(lib)}, {row.file, read_file(lib_dir + row.file)}}, row.cls), row.file);
  }
  const std::string molib = std::string(MO_SOURCE_DIR) + "/modelica/MoLib.mo";
  const std::string cp = std::string(MO_SOURCE_DIR) + "/modelica/CartPendulum/CartPendulumComponents.mo";
  check_round_trip(compile({{molib, read_file(molib)}, {cp, read_file(cp)}}, "CartPendulumComponents"), cp);
}
