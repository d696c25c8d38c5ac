// The morun command line on the cart-pendulum: results with sensitivities,
// the compile cache, and clean failures (diagnostics, exit status, no
// partial output) on bad input.
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "e2e/cli.hpp"
#include "e2e/support.hpp"

namespace fs = std::filesystem;
using namespace mo::e2e;

namespace {

const std::string kCartPendulum = kModelica + "CartPendulum/CartPendulumODE.mo";
const std::string kCommon = quoted(kCartPendulum) + " -c CartPendulumODE --stop-time 2 --input F=sine:3,1";

}  // namespace

TEST_CASE("morun: cart-pendulum with --sensitivities m2 writes result.csv and the rerun is cached") {
  const fs::path dir = scratch("morun_ok");
  const fs::path out = dir / "out";
  const Run first = morun(kCommon + " --sensitivities m2 -o " + quoted(out.string()), dir);
  INFO(first.err);
  REQUIRE(first.status == 0);
  const std::string csv = slurp(out / "result.csv");
  const std::string header = csv.substr(0, csv.find('\n'));
  INFO("header: " << header);
  for (const char* column : {"time", "x", "phi", "v", "w", "y_x", "y_phi", "d(x)/d(m2)", "d(phi)/d(m2)"})
    CHECK(("," + header + ",").find("," + std::string(column) + ",") != std::string::npos);
  CHECK(header.find("d(x)/d(m1)") == std::string::npos);  // only the parameter asked for
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 502);  // header + 501 rows (500 intervals)
  CHECK(fs::exists(out / "summary.json"));
  CHECK(slurp(out / "summary.json").find("\"success\"") != std::string::npos);

  const Run second = morun(kCommon + " --sensitivities m2 -o " + quoted(out.string()), dir);
  INFO(second.err);
  CHECK(second.status == 0);
  CHECK(second.err.find("cached") != std::string::npos);
  CHECK(slurp(out / "result.csv") == csv);  // deterministic
}

TEST_CASE("morun: an unknown parameter in --set fails with a message and writes nothing") {
  const fs::path dir = scratch("morun_bad_set");
  const fs::path out = dir / "out";
  const Run r = morun(kCommon + " --set nosuch=1 -o " + quoted(out.string()), dir);
  INFO(r.err);
  CHECK(r.status != 0);
  CHECK(r.err.find("nosuch") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
}

TEST_CASE("morun: --set of a structural or bound parameter says why it cannot be set") {
  // EvaluatedCapacitance.mo: CapVal has Evaluate = true, C = CapVal is bound.
  struct Case {
    std::string set, why;
  };
  const std::vector<Case> cases{
      {"CapVal=1", "'CapVal': annotation(Evaluate = true) made its value part of the model's structure"},
      {"C=1", "'C': it is bound to other parameters' values; set those"},
      {"v=1", "'v': it is a variable, not a parameter"},
  };
  int k = 0;
  for (const Case& c : cases) {
    CAPTURE(c.set);
    const fs::path dir = scratch("morun_structural_set" + std::to_string(k++));
    const Run r = morun(quoted(kData + "EvaluatedCapacitance.mo") + " --stop-time 1 --set " + c.set + " -o " +
                            quoted((dir / "out").string()),
                        dir);
    CHECK(r.status == 2);
    CHECK(r.err.find("--set: the model has no parameter " + c.why) != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "out"));
  }
}

TEST_CASE("morun: a syntax error gives file.mo:line:col: error: and leaves earlier results untouched") {
  const fs::path dir = scratch("morun_syntax");
  const fs::path bad = dir / "Broken.mo";
  std::ofstream(bad) << "model Broken\n  Real x(start = 1);\nequation\n  der(x) = -x +;\nend Broken;\n";
  const fs::path out = dir / "out";
  fs::create_directories(out);
  std::ofstream(out / "result.csv") << "time,x\n0,1\n";
  const Run r = morun(quoted(bad.string()) + " --stop-time 1 -o " + quoted(out.string()), dir);
  INFO(r.err);
  CHECK(r.status != 0);
  CHECK(std::regex_search(r.err, std::regex(R"(Broken\.mo:4:\d+: error: )")));
  CHECK(slurp(out / "result.csv") == "time,x\n0,1\n");
  CHECK_FALSE(fs::exists(out / "summary.json"));
  std::size_t files = 0;  // no temporaries left behind either
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(out)) ++files;
  CHECK(files == 1);
}

TEST_CASE("morun: a model error (undeclared variable) is reported at its line, exit 1") {
  const fs::path dir = scratch("morun_model_error");
  const fs::path bad = dir / "Undeclared.mo";
  std::ofstream(bad) << "model Undeclared\n  Real x(start = 1);\nequation\n  der(x) = -k*x;\nend Undeclared;\n";
  const fs::path out = dir / "out";
  const Run r = morun(quoted(bad.string()) + " --stop-time 1 -o " + quoted(out.string()), dir);
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(std::regex_search(r.err, std::regex(R"(Undeclared\.mo:4:\d+: error: )")));
  CHECK_FALSE(fs::exists(out));
}

TEST_CASE("morun: --set x.start=v and --sensitivities x.start reach the initial conditions") {
  const fs::path dir = scratch("morun_start");
  const fs::path out = dir / "out";
  const Run r = morun(quoted(kCartPendulum) + " -c CartPendulumODE --stop-time 1 --intervals 10 "
                      "--input F=const:0 --set x.start=0.25 --sensitivities x.start,m2 -o " +
                          quoted(out.string()),
                      dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  std::ifstream in(out / "result.csv");
  std::string header, first;
  std::getline(in, header);
  std::getline(in, first);
  INFO(header << "\n" << first);
  // time, x, phi, v, w, then sensitivities: x starts at 0.25 and d(x)/d(x.start) at 1.
  CHECK(first.rfind("0,0.25,0,0,0,", 0) == 0);
  CHECK(header.find("d(x)/d(x.start)") != std::string::npos);
  const auto columns = [](const std::string& line) {
    std::vector<std::string> fields;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
    return fields;
  };
  const auto names = columns(header), values = columns(first);
  const auto at = std::find(names.begin(), names.end(), "d(x)/d(x.start)") - names.begin();
  CHECK(std::stod(values[static_cast<std::size_t>(at)]) == 1.0);
}

TEST_CASE("morun: --linear-solver picks KLU or dense LU and summary.json says which") {
  // 150 states, two nonzeros per row: auto takes KLU; both give the Erlang CDF.
  const fs::path dir = scratch("morun_linear_solver");
  std::map<std::string, std::string> last_rows;
  for (const std::string choice : {"auto", "klu", "dense"}) {
    CAPTURE(choice);
    const fs::path out = dir / choice;
    const Run r = morun(quoted(kData + "LagChain.mo") + " --stop-time 20 --intervals 4 --rtol 1e-10 --atol 1e-12"
                        " --variables 'x\\[150\\]' --linear-solver " + choice + " -o " + quoted(out.string()),
                        dir);
    INFO(r.err);
    REQUIRE(r.status == 0);
    const std::string summary = slurp(out / "summary.json");
    CHECK(summary.find(std::string("\"linear_solver\": \"") + (choice == "dense" ? "dense" : "klu") + "\"") !=
          std::string::npos);
    std::ifstream in(out / "result.csv");
    std::string line, last;
    while (std::getline(in, line)) last = line;
    last_rows[choice] = last;
  }
  // x_150(20) = P(150, 200), read at the csv's precision.
  double term = std::exp(-200.0), sum = 0.0;
  for (int j = 0; j < 149; ++j) sum += term, term *= 200.0 / (j + 1);
  const double exact = 1.0 - (sum + term);
  for (const auto& [choice, row] : last_rows) {
    CAPTURE(choice, row);
    CHECK(std::stod(row.substr(row.find(',') + 1)) == Approx(exact).margin(1e-7));
  }
  const Run bad = morun(quoted(kData + "LagChain.mo") + " --stop-time 1 --linear-solver lu -o " +
                            quoted((dir / "bad").string()),
                        dir);
  CHECK(bad.status == 2);
  CHECK(bad.err.find("--linear-solver") != std::string::npos);
}
