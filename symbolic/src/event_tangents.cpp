// Derivatives of the event map; see event_tangents.hpp.
#include "mo/symbolic/event_tangents.hpp"

#include <string>

#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic {

namespace {

Expr seed(ExprArena& a, const std::string& base, std::size_t index) {
  std::string name = "$event_seed." + base + "[" + std::to_string(index) + "]";
  for (int k = 1; a.find_symbol(name); ++k)
    name = "$event_seed." + base + "[" + std::to_string(index) + "]#" + std::to_string(k);
  return a.symbol(name, SymbolRole::Algebraic, static_cast<std::int32_t>(index));
}

std::string unused(const ExprArena& a, const std::string& base) {
  std::string name = base;
  for (int k = 1; a.find_symbol(name); ++k) name = base + "#" + std::to_string(k);
  return name;
}

/// The directional map extended by pre(v) → δv for continuous v that appear
/// under pre() in `roots` (pre(v) is v's value when the handler starts).
ExprMap with_pre(const OdeModel& m, const ExprMap& derivative, const std::vector<Expr>& roots) {
  ExprMap out = derivative;
  for (Expr l : leaves(m.arena, roots)) {
    if (m.arena.kind(l) != ExprKind::Pre) continue;
    const auto it = derivative.find(m.arena.operand(l, 0));
    if (it != derivative.end()) out[l] = it->second;
  }
  return out;
}

}  // namespace

EventTangents event_tangents(OdeModel& m) {
  ExprArena& a = m.arena;
  EventTangents t;
  ExprMap seeds;
  for (std::size_t i = 0; i < m.states.size(); ++i) {
    t.seed_x.push_back(seed(a, "x", i));
    seeds[m.states[i].symbol] = t.seed_x.back();
  }
  for (std::size_t k = 0; k < m.parameters.size(); ++k) {
    t.seed_p.push_back(seed(a, "p", k));
    seeds[m.parameters[k].symbol] = t.seed_p.back();
  }
  t.seed_t = seed(a, "t", 0);
  if (m.time.valid()) seeds[m.time] = t.seed_t;
  t.directional = differentiate_steps(
      m, seeds, [&](const std::string& v) { return unused(a, "$event_tangent(" + v + ")"); });
  std::vector<Expr> roots(m.zero_crossings);
  for (const WhenClause& w : m.whens) {
    for (const Assignment& as : w.assignments) roots.push_back(as.value);
    for (const Reinit& r : w.reinits) roots.push_back(r.value);
  }
  const ExprMap map = with_pre(m, t.directional.derivative, roots);
  // One call for all rows: linear in the model's size.
  const std::vector<Expr> d = forward_derivative(a, roots, map, false);
  std::size_t k = 0;
  for (std::size_t i = 0; i < m.zero_crossings.size(); ++i) t.indicators.push_back(d[k++]);
  for (const WhenClause& w : m.whens) {
    WhenTangent wt;
    for (std::size_t i = 0; i < w.assignments.size(); ++i) wt.assignments.push_back(d[k++]);
    for (std::size_t i = 0; i < w.reinits.size(); ++i) wt.reinits.push_back(d[k++]);
    t.whens.push_back(std::move(wt));
  }
  return t;
}

}  // namespace mo::symbolic
