// The structural pattern of second derivatives, read from the expression graph
// of the second directional derivatives D²f_i[σ, τ] = Σ_ab T_i(a, b) σ_a τ_b.
//
// Every node of that graph is, in the seeds, a sum of a seed-free part, a part
// linear in σ, a part linear in τ and a bilinear part. Per node we keep which
// σ columns the σ-linear part uses (Lσ), which τ columns the τ-linear part
// uses (Lτ) and which pairs (a, b) the bilinear part can hold (P):
//   x + y, x − y, −x:        unions;
//   x · y:                   P = P(x) ∪ P(y) ∪ Lσ(x)×Lτ(y) ∪ Lσ(y)×Lτ(x);
//   x / y, y seed-free:      as x;
//   φ(x, …) otherwise:       unions, and P ∪= Lσ×Lτ of the operands' unions
//                            (conservative: φ may be nonlinear in all of them);
//   relations, sign, floor:  piecewise constant, no seed dependence.
// An equation block's unknowns get the union over its residuals, iterated to
// a fixed point (the unknowns appear in the residuals). A row's pairs are then
// the structurally nonzero T_i(a, b) — e.g. the sensitivity equations
// der(s) = J(x)s + ∂f/∂p, linear in s, have no (s, s) pairs, which the
// product of the row's σ and τ dependencies (both {x, s}) would include.
#pragma once

#include <utility>
#include <vector>

#include "mo/symbolic/ode.hpp"

namespace mo::codegen::detail {

/// Per row, the pairs (a, b) with a ≥ b, ascending, at which D²row[σ, τ] can be
/// nonzero; σ_k = sigma[k] and τ_k = tau[k] are column k. Step targets get
/// their dependencies from `steps` (each list in order, lists in order); leaves
/// that are neither seeds nor targets are seed-free. Invalid rows give no pairs.
std::vector<std::vector<std::pair<int, int>>> second_order_pairs(
    const symbolic::ExprArena& arena, const std::vector<symbolic::Expr>& sigma,
    const std::vector<symbolic::Expr>& tau,
    const std::vector<const std::vector<symbolic::Step>*>& steps,
    const std::vector<symbolic::Expr>& rows);

}  // namespace mo::codegen::detail
