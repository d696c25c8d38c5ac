// Issue 14, diagrams in, without Scilab: the diagnostics when Scilab is
// missing, fails or hangs (a stand-in program plays Scilab), and that the
// temporary folder is removed in every case; and the init file Scilab's
// translator writes (another stand-in plays the translator): the fixed flags it
// holds change the initial state, and malformed XML is an error.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>

#include "child_process.hpp"
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

TEST_CASE("diagram: Scilab's Java keeps its temporary files in the private work folder", "[diagram]") {
  // Java ignores TMPDIR: without java.io.tmpdir its font files (+~JF*.tmp)
  // stay in /tmp after every diagram. The user's own _JAVA_OPTIONS come first.
  const fs::path record = scratch("diagram-java-tmpdir-record") / "env.txt";
  const Run r = compile_diagram("diagram-java-tmpdir", {"MO_SCILAB=" + (kData / "env-recording-scilab.sh").string(),
                                                        "DISPLAY=:0", "MO_TEST_RECORD=" + record.string(),
                                                        "_JAVA_OPTIONS=-Xmx512m"});
  CHECK(r.status == 1);  // the stand-in compiles nothing
  std::istringstream lines(slurp(record));
  std::string java, tmpdir;
  std::getline(lines, java);
  std::getline(lines, tmpdir);
  INFO(java << "\n" << tmpdir);
  const std::string work = (fs::path(MO_BINARY_DIR) / "e2e-scratch" / "diagram-java-tmpdir" / "tmp").string();
  REQUIRE(tmpdir.rfind(work + "/mocompile-xcos-", 0) == 0);  // the work folder in the run's TMPDIR
  CHECK(java == "-Xmx512m -Djava.io.tmpdir=" + tmpdir);
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

namespace {

const fs::path kScratch = fs::path(MO_BINARY_DIR) / "e2e-scratch";

/// The first and last value of column `name` of a result.csv.
std::pair<double, double> first_last(const fs::path& csv, const std::string& name) {
  std::istringstream in(slurp(csv));
  std::string line;
  std::getline(in, line);
  std::size_t col = 0, found = std::string::npos;
  for (std::istringstream header(line); std::getline(header, line, ','); ++col)
    if (line == name) found = col;
  REQUIRE(found != std::string::npos);
  std::vector<double> values;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string cell;
    for (std::size_t c = 0; std::getline(row, cell, ','); ++c)
      if (c == found) values.push_back(std::stod(cell));
  }
  REQUIRE(!values.empty());
  return {values.front(), values.back()};
}

/// morun on a diagram whose translation (the files of `translation`) a stand-in
/// Scilab plays, in the fresh scratch folder `name` (results in its out/).
Run run_translated(const std::string& name, const fs::path& translation, bool init_fixed = true) {
  const fs::path dir = scratch(name);
  fs::create_directories(dir / "tmp");
  std::vector<std::string> args{(kData / "SeriesRLC.zcos").string(), "--stop-time", "1", "--rtol", "1e-9", "--atol",
                                "1e-12", "-o", (dir / "out").string()};
  if (init_fixed) args.push_back("--init-fixed");
  const Run r = run_tool(kMorun, args,
                         dir, {"MO_SCILAB=" + (kData / "translating-scilab.sh").string(), "DISPLAY=:0",
                               "MO_FAKE_TRANSLATION=" + translation.string(), "TMPDIR=" + (dir / "tmp").string()});
  CHECK(fs::is_empty(dir / "tmp"));
  return r;
}

}  // namespace

TEST_CASE("diagram init file: with --init-fixed a variable it fixes sets the initial state", "[diagram]") {
  // FixedLag: der(x) = -x, y = 2 x; the flat .mo gives x start 0 and y start 4,
  // the init file says y is fixed: x(0) = 2, x(1) = 2/e. Without --init-fixed
  // (as Scilab's simulation) or without the file, x stays 0.
  const Run with = run_translated("diagram-init-fixed", kData / "init");
  INFO(with.err);
  REQUIRE(with.status == 0);
  CHECK(with.err.find("morun: note: the diagram's init file fixes the start value of 1 variable: FixedLag1.y") !=
        std::string::npos);
  const auto [x0, x1] = first_last(kScratch / "diagram-init-fixed" / "out" / "result.csv", "FixedLag1.x");
  CHECK(x0 == Approx(2.0).epsilon(1e-9));
  CHECK(x1 == Approx(2.0 * std::exp(-1.0)).epsilon(1e-6));

  const fs::path bare = scratch("diagram-init-none-files");
  fs::create_directories(bare);
  fs::copy_file(kData / "init" / "FixedLag_imf.mo", bare / "FixedLag_imf.mo", fs::copy_options::overwrite_existing);
  const Run ignored = run_translated("diagram-init-ignored", kData / "init", false);
  INFO(ignored.err);
  REQUIRE(ignored.status == 0);
  CHECK(ignored.err.find("init file") == std::string::npos);
  CHECK(first_last(kScratch / "diagram-init-ignored" / "out" / "result.csv", "FixedLag1.x").first == 0.0);
  const Run without = run_translated("diagram-init-none", bare);
  INFO(without.err);
  REQUIRE(without.status == 0);
  CHECK(without.err.find("init file") == std::string::npos);
  const auto [y0, y1] = first_last(kScratch / "diagram-init-none" / "out" / "result.csv", "FixedLag1.x");
  CHECK(y0 == 0.0);
  CHECK(y1 == 0.0);
}

TEST_CASE("diagram init file: a flag the model does not declare stays free", "[diagram]") {
  // Two Doublers (der(x) = -x, y = 2 x, y start 4) whose y is fixed when
  // initType > 0: Fixed1 has initType = 1, Free1 0. Scilab's translator marks
  // both y fixed in the init file; the model's own flags fix Fixed1.y alone:
  // Fixed1.x(0) = 2, Free1.x keeps its start 0.
  const Run r = run_translated("diagram-init-declared", kData / "declared-fixed");
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(r.err.find("morun: note: the init file marks fixed, but the model does not fix") != std::string::npos);
  CHECK(r.err.find("block parameter), 1 variable: Free1.y: left free") != std::string::npos);
  CHECK(r.err.find("morun: note: the diagram's init file fixes the start value of 1 variable: Fixed1.y") !=
        std::string::npos);
  CHECK(r.err.find("warning") == std::string::npos);
  const fs::path csv = kScratch / "diagram-init-declared" / "out" / "result.csv";
  CHECK(first_last(csv, "Fixed1.x").first == Approx(2.0).epsilon(1e-9));
  CHECK(first_last(csv, "Free1.x").first == 0.0);

  // Without the hierarchical model the flags are applied as written, with a warning.
  const fs::path partial = scratch("diagram-init-declared-partial-files");
  for (const char* f : {"Declared_imf.mo", "Declared_imf_init.xml"})
    fs::copy_file(kData / "declared-fixed" / f, partial / f, fs::copy_options::overwrite_existing);
  const Run unchecked = run_translated("diagram-init-declared-partial", partial);
  INFO(unchecked.err);
  REQUIRE(unchecked.status == 0);
  CHECK(unchecked.err.find("morun: warning: the init file's fixed flags are taken as they are, unchecked "
                           "(Declared_im.mo is missing beside the init file)") != std::string::npos);
  CHECK(unchecked.err.find("fixes the start value of 2 variables: Free1.y, Fixed1.y") != std::string::npos);
}

TEST_CASE("diagram init file: malformed XML or a DTD is an error with its line", "[diagram]") {
  const fs::path bad = scratch("diagram-init-bad-files");
  fs::create_directories(bad);
  fs::copy_file(kData / "init" / "FixedLag_imf.mo", bad / "FixedLag_imf.mo", fs::copy_options::overwrite_existing);
  std::ofstream(bad / "FixedLag_imf_init.xml") << "<model>\n<terminal>\n<id>x</kind>\n</model>\n";
  const Run r = run_translated("diagram-init-bad", bad);
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("FixedLag_imf_init.xml:3: error: mismatched tag") != std::string::npos);

  std::ofstream(bad / "FixedLag_imf_init.xml")
      << "<?xml version=\"1.0\"?>\n<!DOCTYPE model [<!ENTITY a \"aaaa\">]>\n<model>&a;</model>\n";
  const Run dtd = run_translated("diagram-init-dtd", bad);
  INFO(dtd.err);
  CHECK(dtd.status == 1);
  CHECK(dtd.err.find("FixedLag_imf_init.xml:2: error: a document type declaration (DTD) is not expected") !=
        std::string::npos);
}

TEST_CASE("run_child stops a program that uses no CPU, not one that computes", "[diagram]") {
  // Scilab's Java can hang at start-up waiting on a lock: its process group
  // then uses no CPU, which run_child watches (stall_seconds).
  mo::tools::ChildRun idle;
  idle.argv = {"/bin/sleep", "30"};
  idle.log_file = "/dev/null";
  idle.timeout_seconds = 20;
  idle.stall_seconds = 1.5;
  const auto stalled = mo::tools::run_child(idle);
  CHECK(stalled.outcome == mo::tools::ChildOutcome::stalled);
  CHECK(stalled.seconds < 10);
  mo::tools::ChildRun busy;
  busy.argv = {"/bin/sh", "-c", "while :; do :; done"};
  busy.log_file = "/dev/null";
  busy.timeout_seconds = 4;
  busy.stall_seconds = 1.5;
  CHECK(mo::tools::run_child(busy).outcome == mo::tools::ChildOutcome::timed_out);
}
