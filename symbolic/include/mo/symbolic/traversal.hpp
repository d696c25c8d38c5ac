// Traversals of the expression graph: which nodes and leaves a set of roots
// reaches, in topological order. All traversals use explicit stacks, so graphs
// of any depth are safe.
#pragma once

#include <span>
#include <vector>

#include "mo/symbolic/expr_arena.hpp"

namespace mo::symbolic {

/// Whether a traversal enters the Symbol operand of der(x) and pre(x).
enum class LeafOperands {
  Skip,  ///< der(x), pre(x) are leaves (evaluation, differentiation); so is
         ///< delay(e, T, M), whose T and M are still visited, not its e.
  Visit, ///< x under der(x) is reached too (substitution).
};

/// Every node reachable from `roots`, each once, operands before the nodes
/// that use them (ascending id). Throws std::out_of_range for a bad handle.
std::vector<Expr> topological_order(const ExprArena& arena, std::span<const Expr> roots,
                                    LeafOperands leaf_operands = LeafOperands::Skip);

/// The leaves (Symbol, Der, Pre, Delay nodes) reachable from `roots`,
/// ascending id. The Symbol under a der(x) or pre(x) is not counted unless
/// used directly, nor the leaves of a delayed expression (those of a delay
/// time are).
std::vector<Expr> leaves(const ExprArena& arena, std::span<const Expr> roots);

} // namespace mo::symbolic
