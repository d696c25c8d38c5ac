// Derivatives of the event map; see event_tangents.hpp.
#include "mo/symbolic/event_tangents.hpp"

#include <string>
#include <unordered_map>

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

/// Seeds every state, input, parameter and time, and the discrete variables with
/// `seeded[i]`, with a symbol each (appended to t's seed lists).
ExprMap seed_all(OdeModel& m, const std::vector<bool>& seeded, EventTangents& t) {
  ExprArena& a = m.arena;
  ExprMap seeds;
  for (std::size_t i = 0; i < m.states.size(); ++i) {
    t.seed_x.push_back(seed(a, "x", i));
    seeds[m.states[i].symbol] = t.seed_x.back();
  }
  for (std::size_t i = 0; i < m.inputs.size(); ++i) {
    t.seed_u.push_back(seed(a, "u", i));
    seeds[m.inputs[i].symbol] = t.seed_u.back();
  }
  for (std::size_t k = 0; k < m.parameters.size(); ++k) {
    t.seed_p.push_back(seed(a, "p", k));
    seeds[m.parameters[k].symbol] = t.seed_p.back();
  }
  for (std::size_t i = 0; i < m.discrete.size(); ++i) {
    t.seed_d.push_back(seeded[i] ? seed(a, "d", i) : Expr());
    if (seeded[i]) seeds[m.discrete[i].symbol] = t.seed_d.back();
  }
  t.seed_t = seed(a, "t", 0);
  if (m.time.valid()) seeds[m.time] = t.seed_t;
  t.directional = differentiate_steps(
      m, seeds, [&](const std::string& v) { return unused(a, "$event_tangent(" + v + ")"); });
  return seeds;
}

/// The when-clauses' assigned values, then their reinit values.
std::vector<Expr> when_values(const OdeModel& m) {
  std::vector<Expr> roots;
  for (const WhenClause& w : m.whens) {
    for (const Assignment& as : w.assignments) roots.push_back(as.value);
    for (const Reinit& r : w.reinits) roots.push_back(r.value);
  }
  return roots;
}

}  // namespace

std::vector<bool> discrete_with_tangents(OdeModel& m) {
  std::vector<bool> out(m.discrete.size(), false);
  std::unordered_map<Expr, std::size_t, ExprHash> index;
  for (std::size_t i = 0; i < m.discrete.size(); ++i) index[m.discrete[i].symbol] = i;
  std::vector<Expr> values, targets;
  for (const WhenClause& w : m.whens)
    for (const Assignment& as : w.assignments) {
      values.push_back(as.value);
      targets.push_back(as.target);
    }
  if (values.empty()) return out;
  // To a fixed point: a value read from such a discrete variable moves too.
  for (bool grew = true; grew;) {
    grew = false;
    EventTangents t;
    seed_all(m, out, t);
    const ExprMap map = with_pre(m, t.directional.derivative, values);
    const std::vector<Expr> d = forward_derivative(m.arena, values, map, false);
    for (std::size_t k = 0; k < d.size(); ++k) {
      const auto it = index.find(targets[k]);
      if (it == index.end() || out[it->second] || m.arena.is_constant(d[k], 0.0)) continue;
      out[it->second] = grew = true;
    }
  }
  return out;
}

EventTangents event_tangents(OdeModel& m) {
  EventTangents t;
  std::vector<bool> seeded(m.discrete.size(), false);
  for (const OdeDiscrete& d : m.discrete)
    if (d.sensitivity) seeded[d.sensitivity->discrete] = true;
  seed_all(m, seeded, t);
  ExprArena& a = m.arena;
  std::vector<Expr> roots(m.zero_crossings);
  const std::vector<Expr> values = when_values(m);
  roots.insert(roots.end(), values.begin(), values.end());
  for (const OdeSample& smp : m.samples) {
    roots.push_back(smp.start);
    roots.push_back(smp.interval);
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
  for (std::size_t i = 0; i < m.samples.size(); ++i) {
    t.sample_starts.push_back(d[k++]);
    t.sample_intervals.push_back(d[k++]);
  }
  return t;
}

}  // namespace mo::symbolic
