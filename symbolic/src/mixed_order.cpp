#include "mo/symbolic/mixed_order.hpp"

#include <span>
#include <unordered_set>

#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic {

namespace {

bool reads_any(const ExprArena& arena, std::span<const Expr> roots, const std::unordered_set<Expr>& set) {
  for (const Expr leaf : leaves(arena, roots))
    if (set.contains(leaf)) return true;
  return false;
}

/// The step targets whose value depends on one of `discrete` (transitively).
std::unordered_set<Expr> moved_targets(const OdeModel& model, const std::unordered_set<Expr>& discrete) {
  std::unordered_set<Expr> moved = discrete;
  for (const Step& step : model.steps) {
    if (const auto* as = std::get_if<Assignment>(&step)) {
      if (reads_any(model.arena, std::span(&as->value, 1), moved)) moved.insert(as->target);
      continue;
    }
    const auto& block = std::get<EquationBlock>(step);
    std::vector<Expr> roots = block.residuals;
    for (const BlockEntry& e : block.jacobian) roots.push_back(e.value);
    roots.insert(roots.end(), block.offset.begin(), block.offset.end());
    if (reads_any(model.arena, roots, moved)) moved.insert(block.unknowns.begin(), block.unknowns.end());
  }
  for (const Expr d : discrete) moved.erase(d);
  return moved;
}

}  // namespace

std::vector<bool> every_event_before_steps(const OdeModel& model) {
  std::vector<bool> before(model.whens.size(), false);
  std::unordered_set<Expr> discrete;
  for (const WhenClause& w : model.whens)
    if (w.every_event)
      for (const Assignment& a : w.assignments) discrete.insert(a.target);
  if (discrete.empty()) return before;
  const std::unordered_set<Expr> moved = moved_targets(model, discrete);
  for (std::size_t k = 0; k < model.whens.size(); ++k) {
    const WhenClause& w = model.whens[k];
    if (!w.every_event) continue;
    std::vector<Expr> roots;
    for (const Assignment& a : w.assignments) roots.push_back(a.value);
    for (const Reinit& r : w.reinits) roots.push_back(r.value);
    before[k] = !reads_any(model.arena, roots, moved);
  }
  return before;
}

}  // namespace mo::symbolic
