// The checks of a model's event constructs for the multi-phase collocation:
// its relations matched to indicators, its held values, what it refuses;
// see study_phases.hpp.
#include <algorithm>
#include <unordered_map>

#include "mo/symbolic/event_tangents.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/traversal.hpp"
#include "study_phases.hpp"

namespace mo::tools {

using symbolic::Expr;
using symbolic::ExprArena;
using symbolic::ExprKind;
using symbolic::OdeModel;
using symbolic::SymbolRole;

namespace {

bool is_relation_kind(ExprKind k) {
  return k == ExprKind::Lt || k == ExprKind::Le || k == ExprKind::Gt || k == ExprKind::Ge;
}

bool uses_role(const ExprArena& a, Expr e, std::initializer_list<SymbolRole> roles) {
  for (Expr leaf : symbolic::leaves(a, {&e, 1})) {
    if (a.kind(leaf) != ExprKind::Symbol) continue;
    const SymbolRole r = a.symbol_info(leaf).role;
    for (SymbolRole x : roles)
      if (r == x) return true;
  }
  return false;
}

}  // namespace

RelationMap match_relations(OdeModel& m) {
  RelationMap out;
  out.in_equations.assign(m.zero_crossings.size(), false);
  std::vector<Expr> roots = m.equation_expressions();
  const std::size_t continuous = roots.size();
  for (const auto& w : m.whens) roots.push_back(w.condition);
  std::unordered_map<Expr, bool, symbolic::ExprHash> in_equation;
  for (Expr e : symbolic::topological_order(m.arena, std::vector<Expr>(roots.begin(), roots.begin() + continuous)))
    in_equation[e] = true;
  for (Expr e : symbolic::topological_order(m.arena, roots)) {
    const ExprKind k = m.arena.kind(e);
    if (!is_relation_kind(k)) continue;
    const bool less = k == ExprKind::Lt || k == ExprKind::Le;
    const Expr a = m.arena.operand(e, 0), b = m.arena.operand(e, 1);
    const Expr forward = m.arena.sub(a, b), backward = m.arena.sub(b, a);
    for (std::size_t i = 0; i < m.zero_crossings.size(); ++i) {
      // g = a − b crossing downwards makes a < b true; g = b − a makes a > b true.
      const bool fwd = m.zero_crossings[i] == forward;
      if (!fwd && m.zero_crossings[i] != backward) continue;
      out.entries.push_back({e, i, fwd == less ? 1.0 : 0.0});
      if (in_equation.contains(e)) out.in_equations[i] = true;
      break;
    }
  }
  out.held = symbolic::discrete_with_tangents(m);
  return out;
}

std::vector<Expr> leaves_through_steps(const OdeModel& m, const std::vector<Expr>& roots) {
  std::unordered_map<Expr, std::vector<Expr>, symbolic::ExprHash> defines;  // target → what computes it
  for (const auto& s : m.steps) {
    if (const auto* as = std::get_if<symbolic::Assignment>(&s)) {
      defines[as->target] = {as->value};
      continue;
    }
    const auto& b = std::get<symbolic::EquationBlock>(s);
    for (Expr u : b.unknowns) defines[u] = b.residuals;
  }
  std::unordered_map<Expr, bool, symbolic::ExprHash> seen;
  std::vector<Expr> out, todo = symbolic::leaves(m.arena, roots);
  for (Expr e : todo) seen[e] = true;
  for (std::size_t i = 0; i < todo.size(); ++i) {
    const auto d = defines.find(todo[i]);
    if (d == defines.end()) continue;
    for (Expr leaf : symbolic::leaves(m.arena, d->second)) {
      if (seen[leaf]) continue;
      seen[leaf] = true;
      todo.push_back(leaf);
      out.push_back(leaf);
    }
  }
  return out;
}

namespace {

/// The symbol a leaf stands for (the operand of pre()), or an invalid Expr for a delay.
Expr leaf_symbol(const ExprArena& a, Expr leaf) {
  if (a.kind(leaf) == ExprKind::Symbol) return leaf;
  if (a.kind(leaf) == ExprKind::Pre || a.kind(leaf) == ExprKind::Der) return a.operand(leaf, 0);
  return {};
}

/// True if `condition` changes at time events only: it reads, directly and
/// through the equations, no state, input or time, nor a delay.
bool timed_condition(const OdeModel& m, Expr condition) {
  std::vector<Expr> all = symbolic::leaves(m.arena, {&condition, 1});
  for (Expr e : leaves_through_steps(m, {condition})) all.push_back(e);
  for (Expr leaf : all) {
    const Expr s = leaf_symbol(m.arena, leaf);
    if (!s.valid()) return false;
    const SymbolRole r = m.arena.symbol_info(s).role;
    if (r == SymbolRole::State || r == SymbolRole::Input || r == SymbolRole::Time) return false;
  }
  return true;
}

std::optional<std::size_t> discrete_index(const OdeModel& m, Expr symbol) {
  for (std::size_t j = 0; j < m.discrete.size(); ++j)
    if (m.discrete[j].symbol == symbol) return j;
  return std::nullopt;
}

/// A held value's reads the phases cannot order: another held value (not
/// pre()) but its own clause's targets, or any through the equations.
std::optional<std::string> bad_held_read(const OdeModel& m, const RelationMap& rel, const symbolic::WhenClause& clause,
                                         Expr value) {
  const auto held_symbol = [&](Expr leaf) {
    if (m.arena.kind(leaf) != ExprKind::Symbol) return false;
    const auto j = discrete_index(m, leaf);
    return j && rel.held[*j];
  };
  for (Expr leaf : symbolic::leaves(m.arena, {&value, 1})) {
    if (!held_symbol(leaf)) continue;
    const bool own = std::any_of(clause.assignments.begin(), clause.assignments.end(),
                                 [&](const symbolic::Assignment& a) { return a.target == leaf; });
    if (!own) return m.arena.symbol_info(leaf).name + ", which another clause sets";
  }
  for (Expr leaf : leaves_through_steps(m, {value}))
    if (held_symbol(leaf)) return m.arena.symbol_info(leaf).name + " through the equations";
  return std::nullopt;
}

}  // namespace

std::optional<PhaseRefusal> check_event_constructs(const OdeModel& m, const RelationMap& rel) {
  for (std::size_t i = 0; i < m.zero_crossings.size(); ++i)
    if (rel.in_equations[i] && uses_role(m.arena, m.zero_crossings[i], {SymbolRole::Input}))
      return PhaseRefusal{"the relation " + symbolic::to_modelica(m.arena, m.zero_crossings[i]) +
                              " = 0 of the equations depends on an input: a phase cannot keep its "
                              "mode under a free input",
                          std::nullopt, i};
  for (std::size_t w = 0; w < m.whens.size(); ++w) {
    const auto& clause = m.whens[w];
    const std::string text = "when " + symbolic::to_modelica(m.arena, clause.condition);
    bool single = false;
    for (const auto& e : rel.entries) single = single || e.relation == clause.condition;
    if (!single && (clause.every_event || !timed_condition(m, clause.condition)))
      return PhaseRefusal{text + ": the multi-phase collocation takes when-conditions that are one "
                                 "relation with an event indicator, or that change at time events only "
                                 "(sample(), initial(), discrete variables), not and/or of relations",
                          w, std::nullopt};
    for (const auto& r : clause.reinits)
      if (uses_role(m.arena, r.value, {SymbolRole::Algebraic, SymbolRole::Derivative, SymbolRole::Input}))
        return PhaseRefusal{text + ": reinit(" + m.states[r.state].info.name + ", " +
                                symbolic::to_modelica(m.arena, r.value) +
                                ") reads an algebraic variable or an input; the multi-phase "
                                "collocation takes reinit values over states, parameters, time, "
                                "pre() and discrete variables",
                            w, std::nullopt};
    // A value that is not held is a mode (frozen per phase, its changes
    // found by the re-simulation); a held one is an unknown of each phase.
    for (const auto& a : clause.assignments) {
      const auto j = discrete_index(m, a.target);
      if (!j || !rel.held[*j]) continue;
      const std::string assigned = text + ": " + symbolic::to_modelica(m.arena, a.target) + " := " +
                                   symbolic::to_modelica(m.arena, a.value);
      if (auto why = bad_held_read(m, rel, clause, a.value))
        return PhaseRefusal{assigned + " reads " + *why + "; the multi-phase collocation takes held values "
                                       "that read other held values only through pre()",
                            w, std::nullopt};
    }
  }
  return std::nullopt;
}

}  // namespace mo::tools
