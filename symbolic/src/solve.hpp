// Turning one BLT block into a step: a scalar equation linear in its unknown
// is solved symbolically; anything larger stays a block (linear if its
// Jacobian does not depend on its unknowns and no relation or step function
// of them appears in it, else nonlinear).
#pragma once

#include <span>
#include <vector>

#include "mo/symbolic/ode.hpp"

namespace mo::symbolic::detail {

/// True if some node of `r` that depends on one of `vars` is a relation or a
/// step function (sign, floor, ceil): r is then not affine in them, whatever
/// its derivative says.
bool discontinuous_in(const ExprArena& a, Expr r, std::span<const Expr> vars);

/// The step computing `unknowns` from 0 = `residuals` (same length).
/// `start` gives the first Newton guess of each unknown (nonlinear blocks).
Step solve_block(ExprArena& arena, const std::vector<Expr>& residuals,
                 const std::vector<Expr>& unknowns, const std::vector<double>& start);

/// The event indicators of `roots`: lhs − rhs of every relation not under
/// noEvent(), each distinct indicator once, appended to `out`.
void collect_zero_crossings(ExprArena& arena, const std::vector<Expr>& roots,
                            std::vector<Expr>& out);

}  // namespace mo::symbolic::detail
