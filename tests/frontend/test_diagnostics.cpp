// Every bad input in data/bad/ gets exactly the diagnostics pinned in its
// .expected file (message, location, source line, caret). Run the suite with
// MO_UPDATE_GOLDEN=1 to rewrite the .expected files after a deliberate change.
#include "compile.hpp"

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>

using namespace mo::test;

namespace {
const std::string kBad = std::string(MO_TEST_DATA_DIR) + "/bad/";
const std::string kMoLib = std::string(MO_SOURCE_DIR) + "/modelica/MoLib.mo";

std::string diagnostics_for(const std::string &path) {
  std::string name = std::filesystem::path(path).filename().string();
  std::string cls = name == "missing_class.mo" ? "DoesNotExist" : "";
  return compile({{"MoLib.mo", read_file(kMoLib)}, {"bad/" + name, read_file(path)}}, cls).diagnostics;
}
} // namespace

TEST_CASE("every bad input gets its pinned diagnostics", "[diagnostics]") {
  auto files = list_files(kBad, ".mo");
  REQUIRE(files.size() >= 20);
  bool update = std::getenv("MO_UPDATE_GOLDEN") != nullptr;
  for (const auto &f : files) {
    std::string got = diagnostics_for(f);
    std::string expected_path = f.substr(0, f.size() - 3) + ".expected";
    if (update)
      write_file(expected_path, got);
    INFO("input: " << f);
    CHECK(got.find(": error: ") != std::string::npos);
    CHECK(got == read_file(expected_path));
  }
}

TEST_CASE("diagnostics are capped so garbage cannot flood the output", "[diagnostics]") {
  std::string garbage(5000, '\x01');
  auto r = compile_text(garbage);
  CHECK_FALSE(r.ok());
  CHECK(r.diagnostics.find("more errors not shown") != std::string::npos);
}

TEST_CASE("mocompile exits non-zero on a bad model and zero on a good one", "[diagnostics][cli]") {
  std::string bad = kBad + "unknown_class.mo";
  std::string good = std::string(MO_SOURCE_DIR) + "/modelica/CartPendulum/CartPendulumODE.mo";
  std::string cmd = std::string(MO_MOCOMPILE) + " " + bad + " > /dev/null 2>&1";
  int status = std::system(cmd.c_str());
  CHECK(WEXITSTATUS(status) == 1);
  cmd = std::string(MO_MOCOMPILE) + " " + good + " --class CartPendulumODE > /dev/null 2>&1";
  status = std::system(cmd.c_str());
  CHECK(WEXITSTATUS(status) == 0);
}
