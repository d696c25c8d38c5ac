// What a reader sees (issue 14.2-14.4): timings in every summary.json,
// progress on stderr (plain lines when stderr is a file, none with --quiet),
// figures as PNG and SVG with titles, units and legends, and report.html —
// built by moreport from a small study run — opened in headless Chromium:
// every figure is there as inline SVG and the console stays clean.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdlib>
#include <sstream>
#include <thread>

#include "common.hpp"
#include "e2e/cli.hpp"
#include "e2e/support.hpp"
#include "progress.hpp"
#include "report_html.hpp"

using namespace mo::e2e;
using nlohmann::json;

namespace {

const std::string kCart = kModelica + "CartPendulum/";
const std::string kOde = quoted(kCart + "CartPendulumODE.mo");
const std::string kMoreport = std::string(MO_BINARY_DIR) + "/tools/moreport";

/// morun with environment assignments `env` in front (e.g. "MO_PROGRESS_SECONDS=0.05").
Run morun_env(const std::string& env, const std::string& args, const fs::path& dir) {
  const fs::path err = dir / "stderr.txt";
  const std::string cmd = env + " XDG_CACHE_HOME=" + quoted(std::string(MO_TEST_CACHE_DIR) + "/morun-test-cache") +
                          " " + quoted(kMorun) + " " + args + " >/dev/null 2>" + quoted(err.string());
  const int raw = std::system(cmd.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(err)};
}

int shell(const std::string& cmd) {
  const int raw = std::system(cmd.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

void check_timings(const fs::path& dir) {
  const json s = json::parse(slurp(dir / "summary.json"));
  INFO(dir.string());
  REQUIRE(s.contains("timings_seconds"));
  for (const char* phase : {"flatten", "lower", "generate", "compile", "solve", "simulate", "total"}) {
    INFO(phase);
    REQUIRE(s["timings_seconds"].contains(phase));
    CHECK(s["timings_seconds"][phase].get<double>() >= 0.0);
  }
  CHECK(s["timings_seconds"]["total"].get<double>() > 0.0);
}

/// A reduced cart-pendulum design with figures (20 elements, one start).
std::string design_args(const fs::path& out) {
  return quoted(kCart + "CartPendulumDesign.opt") + " -L " + kOde + " -o " + quoted(out.string()) +
         " --plot --option n_e=20 --option measurements=20 --option 'starts={\"const:0\"}'";
}

struct Chromium {
  int status = -1;
  std::string dom, log;
};

/// Opens `html` in headless Chromium (a fresh profile, no network services)
/// and returns the DOM after load and Chromium's log (console messages).
Chromium open_in_chromium(const std::string& chromium, const fs::path& html, const fs::path& dir) {
  const fs::path profile = dir / "chromium-profile";
  fs::remove_all(profile);
  fs::create_directories(profile);
  const std::string cmd =
      quoted(chromium) +
      " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking"
      " --disable-component-update --disable-sync --user-data-dir=" + quoted(profile.string()) +
      " --enable-logging=stderr --v=0 --dump-dom " + quoted("file://" + fs::absolute(html).string()) + " >" +
      quoted((dir / "dom.html").string()) + " 2>" + quoted((dir / "chromium.log").string());
  Chromium c;
  c.status = shell("timeout 120 " + cmd);
  c.dom = slurp(dir / "dom.html");
  c.log = slurp(dir / "chromium.log");
  return c;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

/// Chromium's log lines that report a console message.
std::string console_lines(const std::string& log) {
  std::string out;
  std::stringstream in(log);
  for (std::string line; std::getline(in, line);)
    if (line.find("CONSOLE") != std::string::npos) out += line + "\n";
  return out;
}

}  // namespace

TEST_CASE("report: a simulation's summary.json has timings for every phase and units") {
  const fs::path dir = scratch("report_sim");
  const Run r = morun(kOde + " -c CartPendulumODE --stop-time 1 --input F=sine:3,1 --sensitivities m2 --plot -o " +
                          quoted((dir / "out").string()),
                      dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  check_timings(dir / "out");
  const json s = json::parse(slurp(dir / "out" / "summary.json"));
  CHECK(s["units"]["x"] == "m");
  CHECK(s["units"]["F"] == "N");
  CHECK(s["units"]["d(x)/d(m2)"] == "m/kg");
  for (const char* f : {"states", "outputs", "sensitivities"}) {
    CHECK(fs::file_size(dir / "out" / (std::string(f) + ".png")) > 1000);
    const std::string svg = slurp(dir / "out" / (std::string(f) + ".svg"));
    CHECK(svg.find("<svg") != std::string::npos);
    CHECK(svg.find("time [s]") != std::string::npos);  // x label with its unit
  }
  // One panel per unit: x [m], phi [rad], v [m/s], w [rad/s] never share an axis.
  const std::string states = slurp(dir / "out" / "states.svg");
  for (const char* label : {"x [m]", "phi [rad]", "v [m/s]", "w [rad/s]"}) {
    INFO(label);
    CHECK(states.find(label) != std::string::npos);
  }
  CHECK(slurp(dir / "out" / "sensitivities.svg").find("[m/kg]") != std::string::npos);
}

TEST_CASE("report: progress lines on stderr, none with --quiet - timings in study summaries") {
  const fs::path dir = scratch("report_progress");
  // A delay and interval of 0.05 s make the reduced design's stages report.
  Run r = morun_env("MO_PROGRESS_SECONDS=0.05", design_args(dir / "loud"), dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(r.err.find("morun: solve: ") != std::string::npos);
  CHECK(r.err.find("iteration") != std::string::npos);
  CHECK(r.err.find("objective") != std::string::npos);
  CHECK(r.err.find('\r') == std::string::npos);  // stderr is a file: plain lines only
  check_timings(dir / "loud");
  // The design's figures, as in the paper's Figs 6-7: bounds dashed, the
  // end-point constraints marked, the sensitivities of the measured outputs.
  const std::string states = slurp(dir / "loud" / "states.svg");
  CHECK(states.find("end-point target") != std::string::npos);
  CHECK(states.find("bound") != std::string::npos);
  CHECK(slurp(dir / "loud" / "inputs.svg").find("bound") != std::string::npos);
  CHECK(fs::exists(dir / "loud" / "sensitivities.svg"));
  const std::string plot_script = slurp(dir / "loud" / "states.gp");
  CHECK(plot_script.find("dt 2") != std::string::npos);  // dashed bounds
  const json s = json::parse(slurp(dir / "loud" / "summary.json"));
  CHECK(s["timings_seconds"].contains("ipopt"));  // the runtime's own solver time is kept

  r = morun_env("MO_PROGRESS_SECONDS=0.05", design_args(dir / "quiet") + " --quiet", dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(r.err.find("morun: solve: ") == std::string::npos);
  CHECK(r.err.find("morun: compile: ") == std::string::npos);
  CHECK(r.err.find("morun: input design") != std::string::npos);  // the result is still reported
  check_timings(dir / "quiet");

  // A multistart in one process says which start it is on; with worker
  // processes, how many starts are done.
  const std::string multi = quoted(kCart + "CartPendulumDesign.opt") + " -L " + kOde +
                            " --option n_e=20 --option measurements=20 --option 'starts={\"const:0\", \"sine:2,0.6\"}'";
  r = morun_env("MO_PROGRESS_SECONDS=0.05", multi + " -j 1 -o " + quoted((dir / "multi").string()), dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(r.err.find("start 2 of 2, best so far") != std::string::npos);
  r = morun_env("MO_PROGRESS_SECONDS=0.05", multi + " -j 2 -o " + quoted((dir / "multi2").string()), dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(r.err.find(" of 2 starts done (2 processes)") != std::string::npos);
  CHECK(r.err.find("local optim") != std::string::npos);
}

TEST_CASE("report: estimation and Monte-Carlo summaries have timings - the fit has a confidence band") {
  const fs::path dir = scratch("report_estimate");
  const fs::path design = dir / "design";
  Run r = morun(design_args(design), dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const std::string input = "F=pwc:" + (design / "designed_input.csv").string();
  r = morun(kOde + " -c CartPendulumODE --stop-time 5 --intervals 100 --measure y_x,y_phi --noise 0.01 --input " +
                quoted(input) + " -o " + quoted((dir / "data").string()),
            dir);
  REQUIRE(r.status == 0);
  // A second experiment with another input: each experiment gets its figure.
  r = morun(kOde + " -c CartPendulumODE --stop-time 5 --intervals 100 --measure y_x,y_phi --noise 0.01 --seed 2"
                   " --input F=sine:3,1 -o " + quoted((dir / "data2").string()),
            dir);
  REQUIRE(r.status == 0);
  const std::string data = "data={\"" + (dir / "data" / "measurements.csv").string() + "\", \"" +
                           (dir / "data2" / "measurements.csv").string() + "\"}";
  r = morun_env("MO_PROGRESS_SECONDS=0.05",
                quoted(kCart + "CartPendulumEstimate.opt") + " -L " + kOde + " -o " + quoted((dir / "est").string()) +
                    " --plot --option n_e=50 --option " + quoted(data) + " --option " +
                    quoted("inputs={\"" + input + "\", \"F=sine:3,1\"}"),
                dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  check_timings(dir / "est");
  const std::string fit = slurp(dir / "est" / "fit.svg");
  CHECK(fit.find("95 % confidence band") != std::string::npos);
  CHECK(fit.find("y_x [m]") != std::string::npos);
  CHECK(fit.find("y_phi [rad]") != std::string::npos);
  CHECK(fit.find("measured") != std::string::npos);
  CHECK(fit.find("experiment 1") != std::string::npos);
  const std::string fit2 = slurp(dir / "est" / "fit_2.svg");
  CHECK(fit2.find("experiment 2") != std::string::npos);
  CHECK(fit2.find("95 % confidence band") != std::string::npos);
  CHECK(fs::exists(dir / "est" / "prediction_2.csv"));
  // The band has width: lower < upper edge somewhere in prediction.csv.
  std::ifstream pred(dir / "est" / "prediction.csv");
  std::string line;
  std::getline(pred, line);
  bool wide = false;
  while (std::getline(pred, line)) {
    std::stringstream ss(line);
    std::vector<double> v;
    for (std::string f; std::getline(ss, f, ',');) v.push_back(std::stod(f));
    if (v.size() >= 4 && v[3] - v[2] > 0) wide = true;
  }
  CHECK(wide);

  r = morun_env("MO_PROGRESS_SECONDS=0.05",
                quoted(kCart + "CartPendulumMonteCarlo.opt") + " -L " + kOde + " -o " + quoted((dir / "mc").string()) +
                    " -j 1 --option seeds=2 --option n_e=50 --option measurements=50 --option " +
                    quoted("inputs={\"F=sine:3,1\"}"),
                dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  check_timings(dir / "mc");
  CHECK(r.err.find("case 1 of 1, ") != std::string::npos);
}

TEST_CASE("report: moreport escapes text, aligns tables and inlines SVG figures with prefixed ids") {
  const fs::path dir = scratch("report_markdown");
  {
    std::ofstream svg(dir / "a.svg");
    svg << "<?xml version=\"1.0\"?>\n<svg viewBox='0 0 10 10'><defs><path id='gpPt0' d='M0 0'/></defs>"
           "<use xlink:href='#gpPt0'/></svg>\n";
  }
  const auto r = mo::tools::markdown_to_html(
      "# T <b>\n\nsome `code` and **bold**\n\n| a | b |\n|---|---:|\n| 1 | 2 |\n\n![cap](a.png)\n\n![gone](b.png)\n",
      dir.string());
  CHECK(r.html.find("<h1>T &lt;b&gt;</h1>") != std::string::npos);
  CHECK(r.html.find("<code>code</code>") != std::string::npos);
  CHECK(r.html.find("<strong>bold</strong>") != std::string::npos);
  CHECK(r.html.find("<td class=\"r\">2</td>") != std::string::npos);
  CHECK(r.figures == 1);
  CHECK(r.html.find("id='f1_gpPt0'") != std::string::npos);
  CHECK(r.html.find("href='#f1_gpPt0'") != std::string::npos);
  CHECK(r.html.find("<?xml") == std::string::npos);
  REQUIRE(r.missing.size() == 1);
  CHECK(r.missing[0] == "b.png");
}

TEST_CASE("report: report.html from a small study opens in headless Chromium with every figure and no console errors") {
  const std::string chromium = mo::tools::find_on_path("chromium");
  if (chromium.empty()) {
    WARN("SKIPPED: chromium is not installed (scripts/install-deps.sh installs it)");
    return;
  }
  const fs::path dir = scratch("report_html");
  const Run r = morun(design_args(dir / "design"), dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  {
    std::ofstream md(dir / "report.md");
    md << "# Small design\n\n| run | criterion |\n|---|---|\n| design | T |\n\n"
          "![designed input](design/inputs.png)\n\n![states](design/states.png)\n\n"
          "![sensitivities](design/sensitivities.png)\n";
  }
  REQUIRE(shell(quoted(kMoreport) + " " + quoted((dir / "report.md").string()) + " -o " +
                quoted((dir / "report.html").string()) + " 2>/dev/null") == 0);
  const std::string html = slurp(dir / "report.html");
  CHECK(html.find("src=\"http") == std::string::npos);  // nothing from the network
  CHECK(html.find("href=\"http") == std::string::npos);

  const Chromium c = open_in_chromium(chromium, dir / "report.html", dir);
  INFO(c.log);
  REQUIRE(c.status == 0);
  CHECK(count(c.dom, "<figure") == 3);
  CHECK(count(c.dom, "<svg") == 3);
  CHECK(c.dom.find("Small design") != std::string::npos);
  CHECK(console_lines(c.log).empty());

  // The console check can fail: a page that logs an error is caught.
  {
    std::ofstream bad(dir / "bad.html");
    bad << "<!DOCTYPE html><html><body><script>console.error('broken page');</script></body></html>\n";
  }
  fs::create_directories(dir / "bad");
  const Chromium b = open_in_chromium(chromium, dir / "bad.html", dir / "bad");
  CHECK(console_lines(b.log).find("broken page") != std::string::npos);
}

TEST_CASE("report: in a log, a stage that ran past the delay has its line even if it ends before the heartbeat") {
  // However the heartbeat thread is scheduled, each stage that ran 2 ms with
  // a delay of 1 ms leaves a line with its detail; --quiet leaves none.
  for (const bool quiet : {false, true}) {
    std::ostringstream out;
    {
      mo::tools::ProgressOptions o;
      o.quiet = quiet;
      o.delay_seconds = o.interval_seconds = 0.001;
      o.tool = "tool";
      mo::tools::Progress progress(out, o);
      for (int k = 0; k < 20; ++k) {
        progress.stage("stage" + std::to_string(k));
        progress.detail("step " + std::to_string(k));
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        progress.end_stage();
      }
    }
    INFO(out.str());
    for (int k = 0; k < 20; ++k)
      CHECK((out.str().find("tool: stage" + std::to_string(k) + ": step " + std::to_string(k) + "; ") !=
             std::string::npos) == !quiet);
  }
}

TEST_CASE("report: mocompile shows its stages on stderr, none with --quiet") {
  const fs::path dir = scratch("report_mocompile_progress");
  fs::create_directories(dir);
  const std::string mocompile = quoted(std::string(MO_BINARY_DIR) + "/tools/mocompile");
  const std::string args = " " + kOde + " --emit cpp -o " + quoted((dir / "cpp").string());
  const fs::path err = dir / "stderr.txt";
  // A delay of 1 ms makes the stages of the cart-pendulum report (at least
  // one of them: the heartbeat thread may be scheduled late on a loaded machine).
  CHECK(shell("MO_PROGRESS_SECONDS=0.001 " + mocompile + args + " 2>" + quoted(err.string())) == 0);
  std::string text = slurp(err);
  INFO(text);
  CHECK((text.find("mocompile: flatten: ") != std::string::npos || text.find("mocompile: lower: ") != std::string::npos ||
         text.find("mocompile: generate: ") != std::string::npos));
  CHECK(text.find('\r') == std::string::npos);  // stderr is a file: plain lines only
  CHECK(shell("MO_PROGRESS_SECONDS=0.001 " + mocompile + " --quiet" + args + " 2>" + quoted(err.string())) == 0);
  text = slurp(err);
  CHECK(text.empty());
}
