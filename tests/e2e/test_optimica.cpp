// Optimica as JModelica writes it (issue 12, items 2 and 3): a free final
// time against the analytic minimum time of a double integrator (with and
// without a value on finalTime, with startTime ≠ 0, exact and limited-memory
// Hessians), bounds on algebraic variables and outputs that are active at
// the optimum, and measuring variables that are not declared outputs
// (morun --measure, a design's outputs, an estimation's data columns).
#include <nlohmann/json.hpp>

#include <cmath>
#include <sstream>

#include "e2e/cli.hpp"
#include "e2e/support.hpp"

using namespace mo::e2e;
using nlohmann::json;

namespace {

json summary(const fs::path& dir) { return json::parse(slurp(dir / "summary.json")); }

/// A CSV file as its header and numeric rows.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  [[nodiscard]] std::size_t column(const std::string& name) const {
    for (std::size_t k = 0; k < header.size(); ++k)
      if (header[k] == name) return k;
    FAIL("no column " + name);
    return 0;
  }
};

Csv read_csv(const fs::path& path) {
  std::ifstream in(path);
  Csv csv;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::stringstream ss(line);
    std::vector<std::string> fields;
    for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
    if (csv.header.empty()) {
      csv.header = fields;
      continue;
    }
    std::vector<double> row;
    for (const auto& f : fields) row.push_back(std::stod(f));
    csv.rows.push_back(row);
  }
  return csv;
}

/// morun on a study file of the test data; requires exit 0.
json solve(const std::string& file, const std::string& options, const fs::path& out) {
  const Run r = morun(quoted(kData + file) + " -o " + quoted(out.string()) + " " + options,
                      out.parent_path());
  INFO(r.err);
  REQUIRE(r.status == 0);
  return summary(out);
}

}  // namespace

TEST_CASE("optimica: minimum-time double integrator reaches tf = 2 (free finalTime)") {
  const fs::path dir = scratch("optimica_min_time");
  for (const std::string hessian : {"exact", "limited_memory"}) {
    INFO(hessian);
    const fs::path out = dir / hessian;
    const json s = solve("MinimumTime.mop", "--option hessian=" + hessian, out);
    CHECK(s["status"] == "success");
    // Bang-bang u = +1 on [0, 1], -1 on [1, 2]: the switch falls on an element
    // boundary (τ = 1/2 of 20 elements), so the discrete optimum is exact.
    CHECK(s["final_time"].get<double>() == Approx(2.0).epsilon(1e-6));
    CHECK(s["objective"].get<double>() == Approx(2.0).epsilon(1e-6));
    CHECK(s["parameters"]["finalTime"].get<double>() == Approx(2.0).epsilon(1e-6));
    CHECK(s["horizon"][1].get<double>() == Approx(2.0).epsilon(1e-6));
    if (hessian == "exact") CHECK(s["nlp"]["hessian_nonzeros"].get<int>() > 0);
    // Results in real time: the last row is at tf with x = 1, v = 0.
    const Csv t = read_csv(out / "trajectories.csv");
    const auto& end = t.rows.back();
    CHECK(end[0] == Approx(2.0).epsilon(1e-6));
    CHECK(end[t.column("x")] == Approx(1.0).margin(1e-7));
    CHECK(end[t.column("v")] == Approx(0.0).margin(1e-7));
    for (const auto& row : t.rows) {  // u = +1 before the switch, -1 after
      if (row[0] < 0.95) CHECK(row[t.column("u")] == Approx(1.0).margin(1e-5));
      if (row[0] > 1.05) CHECK(row[t.column("u")] == Approx(-1.0).margin(1e-5));
    }
    CHECK(s["resimulation"]["max_state_difference"].get<double>() < 1e-6);
  }
}

TEST_CASE("optimica: free finalTime with a value, startTime = 1, time in the model") {
  const fs::path dir = scratch("optimica_min_time_shifted");
  const json s = solve("MinimumTimeShifted.mop", "--option hessian=exact", dir / "out");
  CHECK(s["status"] == "success");
  CHECK(s["final_time"].get<double>() == Approx(3.0).epsilon(1e-6));
  CHECK(s["objective"].get<double>() == Approx(2.0).epsilon(1e-6));  // ∫ 1 dt = tf - t0
  CHECK(s["horizon"][0].get<double>() == 1.0);
  const Csv t = read_csv(dir / "out" / "trajectories.csv");
  CHECK(t.rows.front()[0] == Approx(1.0));
  // s' = time from s(1) = 0: s(3) = (9 - 1)/2 (Radau integrates t exactly).
  CHECK(t.rows.back()[t.column("s")] == Approx(4.0).epsilon(1e-6));
}

TEST_CASE("optimica: a free final time is refused where it has no meaning") {
  const fs::path dir = scratch("optimica_free_time_errors");
  Run r = morun(quoted(kData + "FreeTimeBadPoint.mop") + " -o " + quoted((dir / "a").string()), dir);
  CHECK(r.status == 1);
  CHECK(r.err.find("with a free finalTime, point values may only be at startTime or finalTime") !=
        std::string::npos);
  r = morun(quoted(kData + "MinimumTime.mop") + " --option task=design --option 'parameters={x}'" +
                " -o " + quoted((dir / "b").string()),
            dir);
  CHECK(r.status != 0);
  CHECK(r.err.find("a free finalTime is supported by task optimal_control only") != std::string::npos);
  std::ofstream(dir / "FreeStart.mop")
      << "optimization FreeStart(objective = x(finalTime), startTime(free = true, initialGuess = 0))\n"
         "  Real x(start = 0, fixed = true);\n  input Real u(min = -1, max = 1);\n"
         "equation\n  der(x) = u;\nend FreeStart;\n";
  r = morun(quoted((dir / "FreeStart.mop").string()) + " -o " + quoted((dir / "c").string()), dir);
  CHECK(r.status == 1);
  CHECK(r.err.find("FreeStart.mop:1:") != std::string::npos);
  CHECK(r.err.find("a free startTime is not supported (only finalTime may be free)") != std::string::npos);
}

TEST_CASE("optimica: bounds on an algebraic variable and on an output are enforced") {
  const fs::path dir = scratch("optimica_bounds");
  for (const std::string hessian : {"exact", "limited_memory"}) {
    INFO(hessian);
    // y(max = 1) with y = u: u wants 2, the bound holds it at 1: ∫(u - 2)² = 1.
    json s = solve("AlgebraicBound.mop", "--option hessian=" + hessian, dir / ("alg_" + hessian));
    CHECK(s["status"] == "success");
    CHECK(s["objective"].get<double>() == Approx(1.0).epsilon(1e-6));
    const Csv t = read_csv(dir / ("alg_" + hessian) / "trajectories.csv");
    for (const auto& row : t.rows) CHECK(row[t.column("u")] == Approx(1.0).margin(1e-6));
  }
  // z = x, z(max = 0.3): max x(1) is 0.3 instead of 1.
  const json s = solve("OutputBound.mop", "", dir / "output");
  CHECK(s["status"] == "success");
  CHECK(s["objective"].get<double>() == Approx(-0.3).epsilon(1e-6));
}

TEST_CASE("optimica: morun --measure samples states, algebraic variables and aliases") {
  const fs::path dir = scratch("optimica_measure");
  const Run r = morun(quoted(kData + "Decay.mo") + " -c Decay --stop-time 1 --intervals 10 --rtol 1e-10 "
                      "--atol 1e-12 --input u=const:0 --measure x,a,b -o " + quoted((dir / "sim").string()),
                      dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const Csv m = read_csv(dir / "sim" / "measurements.csv");
  REQUIRE(m.header == std::vector<std::string>{"time", "x", "a", "b"});
  REQUIRE(m.rows.size() == 10);
  for (const auto& row : m.rows) {
    const double x = std::exp(-2.0 * row[0]);
    CHECK(row[1] == Approx(x).epsilon(1e-7));
    CHECK(row[2] == Approx(x * x).epsilon(1e-7));
    CHECK(row[3] == Approx(x).epsilon(1e-7));
  }
  const Run bad = morun(quoted(kData + "Decay.mo") + " -c Decay --stop-time 1 --input u=const:0 "
                        "--measure nothere -o " + quoted((dir / "bad").string()),
                        dir);
  CHECK(bad.status == 2);
  CHECK(bad.err.find("--measure: the model has no variable 'nothere'") != std::string::npos);
}

TEST_CASE("optimica: a design measures a state as it would a declared output") {
  const fs::path dir = scratch("optimica_design_state");
  const std::string file = quoted(kData + "DecayDesign.mop") + " -L " + quoted(kData + "Decay.mo");
  const auto info = [&](const std::string& cls) {
    const fs::path out = dir / cls;
    const Run r = morun(file + " -c " + cls + " -o " + quoted(out.string()), dir);
    INFO(r.err);
    REQUIRE(r.status == 0);
    return summary(out)["design"]["information_resimulated"].get<double>();
  };
  const double state = info("DecayDesignState"), output = info("DecayDesignOutput");
  CHECK(state > 0);
  CHECK(state == Approx(output).epsilon(1e-6));
}

TEST_CASE("optimica: an estimation fits data columns of a state, an algebraic variable and an alias") {
  const fs::path dir = scratch("optimica_estimate_any");
  Run r = morun(quoted(kData + "Decay.mo") + " -c Decay --stop-time 2 --intervals 40 --rtol 1e-10 "
                "--atol 1e-12 --input u=const:0.5 --measure x,a,b -o " + quoted((dir / "sim").string()),
                dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const fs::path out = dir / "est";
  r = morun(quoted(kData + "DecayDesign.mop") + " -L " + quoted(kData + "Decay.mo") +
                " -c DecayEstimate -o " + quoted(out.string()) + " --option " +
                quoted("data={\"" + (dir / "sim" / "measurements.csv").string() + "\"}"),
            dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json e = summary(out)["estimates"][0];
  CHECK(e["name"] == "k");
  CHECK(e["estimate"].get<double>() == Approx(2.0).epsilon(1e-3));  // noise-free data
}
