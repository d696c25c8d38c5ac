// The order of one event iteration's mixed system (mo/symbolic/mixed_order.hpp):
// which discrete equations outside when-clauses are computed from discrete
// values alone (before the continuous steps) and which read the steps.
#include <catch2/catch.hpp>

#include <map>

#include "../frontend/compile.hpp"
#include "mo/symbolic/lower.hpp"
#include "mo/symbolic/mixed_order.hpp"

using namespace mo::symbolic;

namespace {

/// Every-event target name -> before_steps, for the model in `text`.
std::map<std::string, bool> order_of(const std::string& text) {
  auto c = mo::test::compile({{"M.mo", text}}, "");
  REQUIRE(c.ok());
  mo::frontend::SourceManager sm;
  mo::frontend::DiagnosticEngine diags(sm);
  auto m = lower(*c.model, diags);
  REQUIRE(m);
  const std::vector<bool> before = every_event_before_steps(*m);
  REQUIRE(before.size() == m->whens.size());
  std::map<std::string, bool> out;
  for (std::size_t k = 0; k < m->whens.size(); ++k) {
    if (!m->whens[k].every_event) {
      CHECK_FALSE(before[k]);
      continue;
    }
    for (const auto& a : m->whens[k].assignments) out[m->arena.symbol_info(a.target).name] = before[k];
  }
  return out;
}

}  // namespace

TEST_CASE("mixed order: the friction's locked and mode before the steps, the start flags after", "[events]") {
  // The mode machine of Rotational.Interfaces.PartialFriction on one inertia;
  // `free` is a discrete Boolean of time that no mode moves.
  const auto order = order_of(R"(
model M
  Real w(start = 0, fixed = true);
  Real a, tau, sa;
  Boolean free;
  Boolean startForward(start = false, fixed = true);
  Boolean startBackward(start = false, fixed = true);
  Boolean locked(start = false);
  Integer mode(start = 3, fixed = true);
  Integer n(start = 0);
equation
  der(w) = a;
  a = sin(time) - tau;
  free = time > 5;
  startForward = pre(mode) == 0 and sa > 1.2 or initial() and w > 0;
  startBackward = pre(mode) == 0 and sa < -1.2 or initial() and w < 0;
  locked = not free and not (pre(mode) == 1 or startForward or pre(mode) == -1 or startBackward);
  a = if locked then 0 else if startForward then sa - 1.2 else if startBackward then sa + 1.2
    else if pre(mode) == 1 then sa - 1.2 else sa + 1.2;
  tau = if locked then sa else if startForward then 1 else if startBackward then -1
    else if pre(mode) == 1 then 1 else -1;
  mode = if free then 2 else if (pre(mode) == 1 or startForward) and w > 0 then 1
    else if (pre(mode) == -1 or startBackward) and w < 0 then -1 else 0;
  when w > 1 then
    n = pre(n) + 1;
  end when;
end M;
)");
  REQUIRE(order.size() == 5);
  CHECK(order.at("free"));           // time only
  CHECK(order.at("locked"));         // start flags, pre(mode), free: no step a mode moves
  CHECK(order.at("mode"));           // w is a state
  CHECK_FALSE(order.at("startForward"));   // sa comes from the block that reads locked
  CHECK_FALSE(order.at("startBackward"));
}

TEST_CASE("mixed order: no every-event clause, nothing before the steps", "[events]") {
  const auto order = order_of(R"(
model M
  Real x(start = 1, fixed = true);
  Integer n(start = 0);
equation
  der(x) = -x;
  when x < 0.5 then
    n = pre(n) + 1;
  end when;
end M;
)");
  CHECK(order.empty());
}
