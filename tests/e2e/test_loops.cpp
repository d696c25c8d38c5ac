// Nonlinear blocks kept as NLP unknowns in collocation (issue 12, JModelica's
// EliminationExample): the iteration variables of an algebraic loop with sqrt
// become per-point controls, the loop's residuals equality constraints.
// The optimum equals the same problem with the loop solved by hand; the
// transformed model's derivatives equal finite differences.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "codegen/jacobian_check.hpp"
#include "e2e/cli.hpp"
#include "e2e/support.hpp"
#include "mo/symbolic/loop_inputs.hpp"
#include "mo/symbolic/lower.hpp"

using namespace mo;
using namespace mo::e2e;
using nlohmann::json;

namespace {

const std::string kLoops = kData + "loops/";

symbolic::OdeModel lowered_plant() {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  auto flat = tools::load_flat_model({kLoops + "SqrtLoopPlant.mo", "", {}, true}, sources, diags);
  std::optional<symbolic::OdeModel> ode;
  if (flat) ode = symbolic::lower(*flat, diags, {});
  std::ostringstream printed;
  diags.print(printed);
  INFO(printed.str());
  REQUIRE(ode);
  return std::move(*ode);
}

json solve(const std::string& file, const std::string& options, const fs::path& out) {
  const Run r = morun(quoted(kLoops + file) + " -o " + quoted(out.string()) + " --option plot=false " + options,
                      out.parent_path());
  INFO(r.err);
  REQUIRE(r.status == 0);
  return json::parse(slurp(out / "summary.json"));
}

}  // namespace

TEST_CASE("loops: a nonlinear block becomes inputs and residual outputs", "[e2e][loops]") {
  symbolic::OdeModel m = lowered_plant();
  std::size_t nonlinear = 0;
  for (const auto& step : m.steps)
    if (const auto* b = std::get_if<symbolic::EquationBlock>(&step); b && !b->linear) nonlinear += b->unknowns.size();
  REQUIRE(nonlinear == 1);  // torn: one iteration variable
  const std::size_t inputs = m.inputs.size(), outputs = m.outputs.size();
  const symbolic::LoopExposure e = symbolic::expose_nonlinear_blocks(m);
  REQUIRE(e.inputs.size() == 1);
  REQUIRE(e.residuals.size() == 1);
  CHECK(m.inputs.size() == inputs + 1);
  CHECK(m.outputs.size() == outputs + 1);
  CHECK(m.inputs[e.inputs[0].input].info.name == "$iteration(" + e.inputs[0].variable + ")");
  for (const auto& step : m.steps) {
    const auto* b = std::get_if<symbolic::EquationBlock>(&step);
    CHECK((!b || b->linear));
  }
}

TEST_CASE("loops: derivatives of the exposed block equal finite differences", "[e2e][loops]") {
  auto model = codegen::test::compiled("e2e_loops_exposed", [] {
    symbolic::OdeModel m = lowered_plant();
    symbolic::expose_nonlinear_blocks(m);
    return m;
  });
  const auto p = model->info().default_parameters();
  REQUIRE(model->info().inputs.size() == 2);
  // away from the loop's solution: the residual is not zero, every derivative still exact
  for (const auto& [x, w] : {std::pair{2.0, 0.7}, {0.3, 1.9}, {5.0, 0.2}})
    codegen::test::check_jacobians(*model, 0.1, {x}, {0.4, w}, p);
}

TEST_CASE("loops: the optimum through the loop equals the loop solved by hand", "[e2e][loops]") {
  const fs::path dir = scratch("loops_sqrt");
  const json hand = solve("SqrtLoopExplicit.mop", "", dir / "explicit");
  REQUIRE(hand["status"] == "success");
  for (const std::string hessian : {"exact", "limited_memory"}) {
    INFO(hessian);
    const json loop = solve("SqrtLoop.mop", "--option hessian=" + hessian, dir / ("loop_" + hessian));
    CHECK(loop["status"] == "success");
    CHECK(loop["objective"].get<double>() == Approx(hand["objective"].get<double>()).epsilon(1e-6));
  }
}

namespace {

/// Column `name` of a CSV file, with the time column.
std::vector<std::pair<double, double>> csv_column(const fs::path& path, const std::string& name) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) header.push_back(f);
  }
  const auto k = std::size_t(std::find(header.begin(), header.end(), name) - header.begin());
  REQUIRE(k < header.size());
  std::vector<std::pair<double, double>> out;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) row.push_back(std::stod(f));
    out.emplace_back(row[0], row[k]);
  }
  return out;
}

/// The distinct values of a control column in time order.
std::vector<double> distinct(const std::vector<std::pair<double, double>>& column) {
  std::vector<double> out;
  for (const auto& [t, v] : column)
    if (out.empty() || std::abs(out.back() - v) > 1e-9) out.push_back(v);
  return out;
}

}  // namespace

TEST_CASE("loops: blocking factors per input and bounds on control changes", "[e2e][loops]") {
  const fs::path dir = scratch("loops_blocks");
  // u1 on two blocks of two elements, u2 on each element: the mean of t there.
  json s = solve("Blocks.mop", "", dir / "blocks");
  CHECK(s["status"] == "success");
  auto u1 = distinct(csv_column(dir / "blocks" / "trajectories.csv", "u1"));
  auto u2 = distinct(csv_column(dir / "blocks" / "trajectories.csv", "u2"));
  REQUIRE(u1.size() == 2);
  CHECK(u1[0] == Approx(1.0).margin(1e-6));
  CHECK(u1[1] == Approx(3.0).margin(1e-6));
  REQUIRE(u2.size() == 4);
  for (std::size_t k = 0; k < 4; ++k) CHECK(u2[k] == Approx(0.5 + double(k)).margin(1e-6));
  // |Δu2| ≤ 0.5: least squares with every step at the bound, centred on the mean 2.
  s = solve("Blocks.mop", "--option 'du_bounds={\"u2=0.5\"}'", dir / "du");
  CHECK(s["status"] == "success");
  u2 = distinct(csv_column(dir / "du" / "trajectories.csv", "u2"));
  REQUIRE(u2.size() == 4);
  for (std::size_t k = 0; k < 4; ++k) CHECK(u2[k] == Approx(1.25 + 0.5 * double(k)).margin(1e-6));
  // A control that does not exist is named.
  const Run bad = morun(quoted(kLoops + "Blocks.mop") + " -o " + quoted((dir / "bad").string()) +
                            " --option 'du_bounds={\"v=1\"}'", dir);
  CHECK(bad.status != 0);
  CHECK(bad.err.find("'v' is not a control of the problem (controls: u1, u2)") != std::string::npos);
}

TEST_CASE("loops: initial guesses from a Dymola textual result and a CSV result", "[e2e][loops]") {
  const fs::path dir = scratch("loops_init_result");
  // max_iter = 0 returns the initial guess itself.
  for (const std::string file : {"guess_dymola.txt", "guess.csv"}) {
    INFO(file);
    const fs::path out = dir / file;
    const Run r = morun(quoted(kLoops + "Blocks.mop") + " -o " + quoted(out.string()) +
                            " --option plot=false --option max_iter=0 --option 'init_result=\"" + file + "\"'", dir);
    INFO(r.err);
    REQUIRE(fs::exists(out / "trajectories.csv"));
    for (const auto& [t, x1] : csv_column(out / "trajectories.csv", "x1")) CHECK(x1 == Approx(7 + t).margin(1e-9));
    if (file == "guess_dymola.txt")  // a negated column (dataInfo −3): x2 = −(1 + t/2)
      for (const auto& [t, x2] : csv_column(out / "trajectories.csv", "x2")) CHECK(x2 == Approx(-(1 + t / 2)).margin(1e-9));
    else {  // the control's column u2 = 1 + t, sampled at each element's midpoint
      const auto u2 = distinct(csv_column(out / "trajectories.csv", "u2"));
      REQUIRE(u2.size() == 4);
      for (std::size_t k = 0; k < 4; ++k) CHECK(u2[k] == Approx(1.5 + double(k)).margin(1e-9));
    }
  }
  const Run bad = morun(quoted(kLoops + "Blocks.mop") + " -o " + quoted((dir / "bad").string()) +
                            " --option 'init_result=\"SqrtLoop.mop\"'", dir);
  CHECK(bad.status != 0);
  CHECK(bad.err.find("init_result") != std::string::npos);
}

TEST_CASE("loops: controls per collocation point (piecewise_constant_controls = false)", "[e2e][loops]") {
  const fs::path dir = scratch("loops_per_point");
  // u1 keeps its blocks; u2 tracks t exactly at every collocation point: ∫(u2 − t)² = 0,
  // and ∫(u1 − t)² over two blocks of length 2 is 2·(2³/12) = 4/3.
  const json s = solve("Blocks.mop", "--option piecewise_constant_controls=false", dir / "pp");
  CHECK(s["status"] == "success");
  CHECK(s["objective"].get<double>() == Approx(4.0 / 3.0).epsilon(1e-6));
}
