#include "mo/symbolic/substitute.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/traversal.hpp"
#include "node_set.hpp"

namespace mo::symbolic {

std::vector<Expr> substitute(ExprArena& arena, std::span<const Expr> exprs,
                             const ExprMap& replacements) {
  for (const auto& [key, value] : replacements) {
    if (!arena.is_leaf(key))
      throw std::invalid_argument("substitute(): key " + to_modelica(arena, key) +
                                  " is not a symbol, der() or pre()");
    arena.kind(value); // throws for a bad handle
  }
  const std::vector<Expr> order = topological_order(arena, exprs, LeafOperands::Visit);
  const detail::OrderIndex index(order);
  std::vector<Expr> rebuilt(order.size());
  Expr operands[3];
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Expr e = order[i];
    if (const auto found = replacements.find(e); found != replacements.end()) {
      rebuilt[i] = found->second;
      continue;
    }
    const ExprKind k = arena.kind(e);
    const std::size_t n = arity(k);
    bool changed = false;
    for (std::size_t j = 0; j < n; ++j) {
      operands[j] = rebuilt[index.position(arena.operand(e, j))];
      changed = changed || operands[j] != arena.operand(e, j);
    }
    if (!changed) {
      rebuilt[i] = e;
      continue;
    }
    if ((k == ExprKind::Der || k == ExprKind::Pre) && arena.kind(operands[0]) != ExprKind::Symbol)
      throw std::invalid_argument("substitute(): " + to_modelica(arena, e) +
                                  " would apply to the non-variable " +
                                  to_modelica(arena, operands[0]) + "; replace it as well");
    rebuilt[i] = arena.make(k, std::span<const Expr>(operands, n));
  }
  std::vector<Expr> result;
  result.reserve(exprs.size());
  for (const Expr e : exprs) result.push_back(rebuilt[index.position(e)]);
  return result;
}

void substitute_in_place(ExprArena& arena, std::span<Expr* const> targets,
                         const ExprMap& replacements) {
  if (targets.empty() || replacements.empty()) return;
  std::vector<Expr> exprs;
  exprs.reserve(targets.size());
  for (Expr* t : targets) exprs.push_back(*t);
  const std::vector<Expr> out = substitute(arena, exprs, replacements);
  for (std::size_t i = 0; i < targets.size(); ++i) *targets[i] = out[i];
}

Expr substitute(ExprArena& arena, Expr e, const ExprMap& replacements) {
  return substitute(arena, std::span<const Expr>(&e, 1), replacements).front();
}

std::vector<Expr> delay_leaves(const ExprArena& arena, std::span<const Expr> roots) {
  std::vector<Expr> found;
  detail::NodeSet seen(16);
  std::vector<Expr> work(roots.begin(), roots.end());
  while (!work.empty()) {
    std::vector<Expr> next;
    for (Expr leaf : leaves(arena, work))
      if (arena.kind(leaf) == ExprKind::Delay && seen.insert(leaf)) {
        found.push_back(leaf);
        next.push_back(arena.operand(leaf, 0));
      }
    work = std::move(next);
  }
  std::sort(found.begin(), found.end());
  return found;
}

Expr undelayed(ExprArena& arena, Expr e) {
  const std::vector<Expr> delays = delay_leaves(arena, std::span(&e, 1));
  if (delays.empty()) return e;
  ExprMap start;  // ascending ids: a delayed expression's own delays come first
  for (Expr d : delays) start[d] = substitute(arena, arena.operand(d, 0), start);
  return substitute(arena, e, start);
}

} // namespace mo::symbolic
