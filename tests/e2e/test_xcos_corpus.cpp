// Issue 10: every diagram of the Xcos corpus (<shared>/xcos-corpus, real Xcos
// files from Coselica's and Scilab's demos) flattens from both of its files,
// lowers, simulates and matches Scilab's own simulation (bench/xcos_corpus.hpp
// has the steps and tolerances). Skipped when the corpus is absent.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>

#include "xcos_corpus.hpp"

using namespace mo::xcos_corpus;

namespace {

/// Scilab (MO_SCILAB or on PATH) and xvfb-run: the corpus check can list a diagram's blocks.
bool scilab_available() {
  auto on_path = [](const std::string& name) {
    const char* path = std::getenv("PATH");
    for (std::string p = path ? path : ""; !p.empty();) {
      const auto colon = p.find(':');
      if (std::filesystem::exists(std::filesystem::path(p.substr(0, colon)) / name)) return true;
      p = colon == std::string::npos ? "" : p.substr(colon + 1);
    }
    return false;
  };
  const char* given = std::getenv("MO_SCILAB");
  return (given && *given ? std::filesystem::exists(given) : on_path("scilab")) && on_path("xvfb-run");
}

}  // namespace

TEST_CASE("every Xcos corpus diagram matches Scilab", "[xcos][corpus]") {
  const auto corpus = corpus_dir(MO_SOURCE_DIR);
  if (!corpus) {
    WARN("SKIPPED: no xcos-corpus beside the checkout (set MO_SHARED_DIR)");
    return;
  }
  ::setenv("XDG_CACHE_HOME", MO_TEST_CACHE_DIR "/morun-test-cache", 1);  // never $HOME
  const Libraries libs{*corpus + "/../third_party/coselica/Coselica.mo", MO_SCILAB_MACROS};
  // Known failures, each explained in docs/xcos-dialect.md ("Why the others
  // fail"). A listed diagram that starts passing fails this test too, so the
  // list only shrinks. ControlledTemperature passes closed through its
  // non-Modelica blocks, which needs Scilab to list them; without Scilab its
  // relay is driven from the recording, which cannot resolve its pulses.
  std::set<std::string> known_failures;
  if (!scilab_available()) {
    WARN("Scilab or xvfb-run is not installed: ControlledTemperature runs open-loop (a known failure)");
    known_failures.insert("ControlledTemperature");
  }
  for (const auto& name : diagrams(*corpus)) {
    const DiagramResult r = check_diagram(*corpus, name, libs);
    INFO(table_row(r));
    if (known_failures.contains(name)) WARN("known failure: " << table_row(r));
    CHECK(r.passed() == !known_failures.contains(name));
  }
}

// ControlledTemperature's known failure is the recording's, not the model's:
// its heater is switched by a non-Modelica relay whose on-pulses (~10 ms)
// fall between Scilab's samples (20 ms), so the recorded input column cannot
// place them. Closed instead through Modelica copies of the diagram's relay,
// set point and sum (tests/e2e/data/xcos_ControlledTemperature_loop.mo), the
// model matches Scilab's run to 1e-3 of range, the relay's samples included.
TEST_CASE("ControlledTemperature closed through its relay matches Scilab", "[xcos][corpus]") {
  const auto corpus = corpus_dir(MO_SOURCE_DIR);
  if (!corpus) {
    WARN("SKIPPED: no xcos-corpus beside the checkout (set MO_SHARED_DIR)");
    return;
  }
  ::setenv("XDG_CACHE_HOME", MO_TEST_CACHE_DIR "/morun-test-cache", 1);
  const StepResult r = check_closed_loop(*corpus, "ControlledTemperature",
                                         MO_SOURCE_DIR "/tests/e2e/data/xcos_ControlledTemperature_loop.mo", "plant");
  INFO(r.detail);
  CHECK(r.passed);
}
