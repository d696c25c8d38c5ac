// Substitution: rebuild expressions with some leaves replaced by other
// expressions, e.g. alias elimination (x := y, z := -y). Rebuilt nodes go
// through the factories, so folding and rewrites apply to the result.
#pragma once

#include <span>
#include <vector>

#include "mo/symbolic/expr_arena.hpp"

namespace mo::symbolic {

/// `exprs` with every key of `replacements` (a Symbol, Der or Pre node)
/// replaced by its value; each node rebuilt once, iteratively. der(x) and
/// pre(x) follow a replaced x only if x maps to a Symbol; otherwise (unless
/// der(x) is a key itself) std::invalid_argument. Non-leaf keys throw too.
/// One pass: the replacement values are not substituted into.
std::vector<Expr> substitute(ExprArena& arena, std::span<const Expr> exprs,
                             const ExprMap& replacements);

/// Rewrites every *targets[i] in place with one call of the span overload
/// (keys are validated once, shared nodes rebuilt once): the way to apply a
/// large map to many expressions in linear time.
void substitute_in_place(ExprArena& arena, std::span<Expr* const> targets,
                         const ExprMap& replacements);

/// One expression; see the span overload.
Expr substitute(ExprArena& arena, Expr e, const ExprMap& replacements);

/// `e` at the start time: every delay(d, T, Tmax) replaced by d (MLS
/// 3.7.2.4: delay(d) is d(t0) until t0 + T), nested delays too.
Expr undelayed(ExprArena& arena, Expr e);

/// The Delay leaves `roots` read, and those their delayed expressions read
/// (delay(delay(x, 1), 1)), by ascending id.
std::vector<Expr> delay_leaves(const ExprArena& arena, std::span<const Expr> roots);

} // namespace mo::symbolic
