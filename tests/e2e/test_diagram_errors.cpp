// Issue 14, diagrams in, without Scilab: the diagnostics when Scilab is
// missing, fails or hangs (a stand-in program plays Scilab), and that the
// temporary folder is removed in every case.
#include <catch2/catch.hpp>

#include <chrono>

#include "e2e/diagram_cli.hpp"

using namespace mo::e2e;

namespace {

const fs::path kData = fs::path(MO_TEST_DATA_DIR) / "xcos";

/// Runs mocompile on the test diagram with `env`, TMPDIR in the scratch folder.
Run compile_diagram(const std::string& name, std::vector<std::string> env, std::vector<std::string> args = {}) {
  const fs::path dir = scratch(name);
  fs::create_directories(dir / "tmp");
  env.push_back("TMPDIR=" + (dir / "tmp").string());
  args.insert(args.begin(), (kData / "SeriesRLC.zcos").string());
  Run r = run_tool(kMocompile, args, dir, env);
  CHECK(fs::is_empty(dir / "tmp"));  // the private work folder is gone
  return r;
}

}  // namespace

TEST_CASE("diagram without Scilab: the diagnostic says what to install", "[diagram]") {
  const Run r = compile_diagram("diagram-no-scilab", {"MO_SCILAB=", "PATH=/nonexistent"});
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("SeriesRLC.zcos: error: reading an Xcos diagram needs Scilab") != std::string::npos);
  CHECK(r.err.find("apt-get install scilab xvfb xauth") != std::string::npos);
  CHECK(r.err.find("MO_SCILAB") != std::string::npos);
}

TEST_CASE("diagram with MO_SCILAB naming no program: error", "[diagram]") {
  const Run r = compile_diagram("diagram-bad-mo-scilab", {"MO_SCILAB=/nonexistent/scilab"});
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("MO_SCILAB='/nonexistent/scilab' is not an executable program") != std::string::npos);
}

TEST_CASE("diagram with a Scilab that does nothing: error, with what it printed", "[diagram]") {
  const Run r = compile_diagram("diagram-scilab-fails", {"MO_SCILAB=/bin/true", "DISPLAY=:0", "PATH=/usr/bin:/bin"});
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("SeriesRLC.zcos: error: Scilab stopped before compiling the diagram") != std::string::npos);
}

TEST_CASE("diagram with a Scilab that hangs: stopped at --scilab-timeout", "[diagram]") {
  const auto start = std::chrono::steady_clock::now();
  const Run r = compile_diagram("diagram-scilab-hangs", {"MO_SCILAB=" + (kData / "hanging-scilab.sh").string(), "DISPLAY=:0"},
                                {"--scilab-timeout", "1"});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("Scilab did not finish compiling the diagram within 1 s and was stopped") != std::string::npos);
  CHECK(seconds < 20.0);
}

TEST_CASE("diagram: --scilab-lib must be a folder", "[diagram]") {
  const Run r = compile_diagram("diagram-bad-lib", {}, {"--scilab-lib", "/nonexistent/coselica"});
  CHECK(r.status == 2);
  const Run env = compile_diagram("diagram-bad-lib-env", {"MO_SCILAB=/bin/true", "MO_SCILAB_LIBS=/nonexistent/coselica"});
  INFO(env.err);
  CHECK(env.status == 1);
  CHECK(env.err.find("block library '/nonexistent/coselica' is not a folder") != std::string::npos);
  const fs::path odd = scratch("diagram-odd-lib") / "lib\"$(touch x)";
  fs::create_directories(odd);
  const Run quote = compile_diagram("diagram-odd-lib-run", {"MO_SCILAB=/bin/true"}, {"--scilab-lib", odd.string()});
  INFO(quote.err);
  CHECK(quote.status == 1);
  CHECK(quote.err.find("names with line breaks, quotes, ` $ or \\ are not supported") != std::string::npos);
}

TEST_CASE("diagram: SIGTERM to mocompile stops Scilab and removes the temporary folder", "[diagram]") {
  const fs::path dir = scratch("diagram-sigterm");
  fs::create_directories(dir / "tmp");
  const fs::path err = dir / "stderr.txt";
  // The stand-in Scilab sleeps 60 s; mocompile is terminated after 1 s.
  const std::string cmd = "cd " + quoted(dir.string()) + " && { env TMPDIR=" + quoted((dir / "tmp").string()) +
                          " MO_SCILAB=" + quoted((kData / "hanging-scilab.sh").string()) + " DISPLAY=:0 " +
                          quoted(kMocompile) + " " + quoted((kData / "SeriesRLC.zcos").string()) + " 2>" +
                          quoted(err.string()) + " & pid=$!; sleep 1; kill -TERM $pid; wait $pid; }";
  const auto start = std::chrono::steady_clock::now();
  const int raw = std::system(cmd.c_str());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string text = slurp(err);
  INFO(text);
  CHECK(WIFEXITED(raw));
  CHECK(WEXITSTATUS(raw) == 1);
  CHECK(text.find("SeriesRLC.zcos: error: interrupted; Scilab was stopped") != std::string::npos);
  CHECK(seconds < 20.0);
  CHECK(fs::is_empty(dir / "tmp"));
}
