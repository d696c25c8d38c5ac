#include "mo/symbolic/traversal.hpp"

#include <algorithm>

#include "node_set.hpp"

namespace mo::symbolic {

namespace {

// Reachable nodes; when `stop_at_leaves`, the operand of der/pre is skipped,
// and the delayed expression of a delay() (its delay times are visited).
std::vector<Expr> reachable(const ExprArena& arena, std::span<const Expr> roots,
                            bool stop_at_leaves) {
  detail::NodeSet seen(roots.size() * 4);
  std::vector<Expr> found;
  std::vector<Expr> stack(roots.begin(), roots.end());
  while (!stack.empty()) {
    const Expr e = stack.back();
    stack.pop_back();
    if (!seen.insert(e)) continue;
    found.push_back(e);
    if (stop_at_leaves && arena.is_leaf(e)) {
      if (arena.kind(e) == ExprKind::Delay) {
        stack.push_back(arena.operand(e, 1));
        stack.push_back(arena.operand(e, 2));
      }
      continue;
    }
    const std::size_t n = arity(arena.kind(e));
    for (std::size_t i = 0; i < n; ++i) stack.push_back(arena.operand(e, i));
  }
  // Operands are created before their users, so ascending id is topological.
  std::sort(found.begin(), found.end());
  return found;
}

} // namespace

std::vector<Expr> topological_order(const ExprArena& arena, std::span<const Expr> roots,
                                    LeafOperands leaf_operands) {
  return reachable(arena, roots, leaf_operands == LeafOperands::Skip);
}

std::vector<Expr> leaves(const ExprArena& arena, std::span<const Expr> roots) {
  std::vector<Expr> order = reachable(arena, roots, true);
  std::erase_if(order, [&](Expr e) { return !arena.is_leaf(e); });
  return order;
}

} // namespace mo::symbolic
