// State selection of issue 10: dummy derivatives chosen by rank over a whole
// level (tiered matching), and a state never moved through a scaled alias.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "../frontend/compile.hpp"
#include "../../symbolic/src/dummy_pivots.hpp"
#include "../../symbolic/src/tiered_matching.hpp"
#include "mo/symbolic/lower.hpp"

using namespace mo;
using mo::symbolic::detail::CostEdge;
using mo::symbolic::detail::tiered_matching;

namespace {

/// The lowered model of a compiled one (both steps required to succeed).
std::optional<symbolic::OdeModel> lowered(const test::Compiled& c) {
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  auto ode = symbolic::lower(*c.model, diags, {});
  REQUIRE(ode);
  return ode;
}

}  // namespace

TEST_CASE("tiered matching: cheap edges win over the whole level, not row by row", "[lower][states]") {
  // Row 0 may take column 0 (cost 10) or 1 (13); row 1 only column 0 (10) or 2 (14).
  // Row by row, row 0 would take column 0 and leave row 1 with cost 14.
  const std::vector<std::vector<CostEdge>> rows{{{0, 10}, {1, 13}}, {{0, 10}, {2, 14}}};
  CHECK(tiered_matching(rows, 3) == std::vector<int>{1, 0});
}

TEST_CASE("tiered matching is maximum", "[lower][states]") {
  const std::vector<std::vector<CostEdge>> rows{{{0, 1}}, {{0, 1}, {1, 5}}, {{1, 2}, {2, 9}}};
  const auto m = tiered_matching(rows, 3);
  CHECK(m == std::vector<int>{0, 1, 2});
  CHECK(tiered_matching({{{0, 1}}, {{0, 1}}}, 1)[1] == -1);
}

TEST_CASE("a differentiated variable is not eliminated through a scaled alias", "[lower][states]") {
  const test::Compiled c = test::compile_text(R"(
    model ScaledCapacitor
      parameter Real R = 1000, C = 1e-3, V = 5;
      Real vc;
      Real ic, vr, ir;
    equation
      C*der(vc) = ic;
      ic = ir;
      vr = R*ir;
      vc = V - vr;
    end ScaledCapacitor;)");
  const auto ode = lowered(c);
  REQUIRE(ode->states.size() == 1);
  CHECK(ode->states[0].info.name == "vc");
}

TEST_CASE("dummy pivots: a structurally valid but singular choice is found and replaced", "[lower][states]") {
  using mo::symbolic::detail::regular_choice;
  using mo::symbolic::detail::regular_columns;
  // Columns: der(i1), der(i2), der(i3), der(i0), der(ia), der(ib). Rows: the
  // open star point, the zero sequence, the two space-phasor rows.
  const double c = -1.0 / 3, s = 1 / std::sqrt(3.0);
  const mo::symbolic::detail::DenseJacobian jac{{1, 1, 1, 0, 0, 0},
                                               {-1, -1, -1, -3, 0, 0},
                                               {2.0 / 3, c, c, 0, -1, 0},
                                               {0, s, -s, 0, 0, -1}};
  // By structure, i1, i2, i3 and ia are dummies: the first two rows then
  // fix the same sum.
  CHECK_FALSE(regular_choice(jac, {0, 1, 2, 4}));
  CHECK(regular_choice(jac, {0, 3, 1, 2}));
  // Phase currents are the cheaper dummies; i0 is taken where it must be.
  const auto columns = regular_columns(jac, {10, 10, 10, 18, 18, 18});
  REQUIRE(columns);
  CHECK(regular_choice(jac, *columns));
  CHECK(std::count(columns->begin(), columns->end(), 3) == 1);
  CHECK(std::count(columns->begin(), columns->end(), 4) == 0);
  CHECK(std::count(columns->begin(), columns->end(), 5) == 0);
  // A row that is a combination of the others has no column.
  CHECK_FALSE(regular_columns({{1, 2}, {2, 4}}, {0, 0}));
  // Rows left without a dummy are outside the block.
  CHECK(regular_choice(jac, {0, -1, -1, -1}));
}

TEST_CASE("an explicit stateSelect outlives the alias that carried it", "[lower][states]") {
  // A slider on a crank, s = L sin(phi): either (s, v) or (phi, w) are the
  // states. The slider's own position avoids being one (as the MSL's Body
  // declares r_0), and the connector's alias of it, which the equations
  // differentiate, says nothing; alias elimination keeps the connector's
  // name. The avoid used to be lost with the slider's name, and s became the
  // state, phi solved from s = L sin(phi): singular at phi = pi/2 (the MSL's
  // GyroscopicEffects solved a body's orientation from positions so).
  const test::Compiled c = test::compile_text(R"(
    model SliderCrank
      parameter Real L = 0.5, m = 2, J = 0.1;
      Real s(start = 0.1, stateSelect = StateSelect.avoid) "slider position";
      Real s_frame "the connector's position";
      Real v, phi, w, F;
    equation
      s_frame = s;
      der(s_frame) = v;
      m*der(v) = F;
      der(phi) = w;
      J*der(w) = -F*L*cos(phi) + sin(time);
      L*sin(phi) - s_frame = 0;
    end SliderCrank;)");
  const auto ode = lowered(c);
  std::vector<std::string> states;
  for (const auto& x : ode->states) states.push_back(x.info.name);
  std::sort(states.begin(), states.end());
  CHECK(states == std::vector<std::string>{"phi", "w"});
}
