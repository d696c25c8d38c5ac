// Symbolic differentiation of expression graphs. A derivative is again a
// graph in the same arena; every node is differentiated once, so the
// derivative of a graph with N nodes has O(N) nodes (no expression swell).
// Leaves are Symbol, der(x) and pre(x) nodes; der(x) and pre(x) are
// independent of x: a caller who wants d der(x) = ... seeds der(x) itself.
//
// Rules worth knowing: d abs(x) = sign(x)*dx (0 at x = 0, a subgradient);
// d min(a,b) = if a < b then da else db (max with >), so at a tie the second
// operand's derivative; d if c then a else b = if c then da else db;
// relations, logic, sign, floor, ceil: 0; d noEvent(x) = noEvent(dx);
// d smooth(p, x) = smooth(max(p-1, 0), dx). Second derivatives: apply again.
#pragma once

#include <span>
#include <vector>

#include "mo/symbolic/expr_arena.hpp"

namespace mo::symbolic {

/// Forward mode: the directional derivative of each output, given the
/// derivative (seed) of each leaf; unseeded leaves have derivative 0.
/// Throws std::invalid_argument if a seed key is not a leaf.
/// `check_seeds = false` skips the O(|seeds|) key check: for callers that
/// validated a large seed map once and differentiate many times with it.
std::vector<Expr> forward_derivative(ExprArena& arena, std::span<const Expr> outputs,
                                     const ExprMap& seeds, bool check_seeds = true);

/// Forward mode for one output; see the span overload.
Expr forward_derivative(ExprArena& arena, Expr output, const ExprMap& seeds);

/// Forward mode with respect to one leaf: d output / d wrt.
/// Throws std::invalid_argument if `wrt` is not a leaf.
Expr derivative(ExprArena& arena, Expr output, Expr wrt);

/// Reverse mode (adjoint accumulation): d output / d wrt[i] for each i, as
/// graphs; 0 where output does not depend on wrt[i]. Only nodes on a path
/// to some wrt[i] get adjoints. Throws std::invalid_argument if a wrt entry
/// is not a leaf or appears twice.
std::vector<Expr> gradient(ExprArena& arena, Expr output, std::span<const Expr> wrt);

} // namespace mo::symbolic
