// Nonlinear blocks kept as NLP unknowns in collocation (issue 12, JModelica's
// EliminationExample): the iteration variables of an algebraic loop with sqrt
// become per-point controls, the loop's residuals equality constraints.
// The optimum equals the same problem with the loop solved by hand; the
// transformed model's derivatives equal finite differences.
#include <nlohmann/json.hpp>

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
