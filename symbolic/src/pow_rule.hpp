// The partial derivative of a^b with respect to its exponent, shared by the
// forward and reverse modes.
#pragma once

#include "mo/symbolic/expr_arena.hpp"

namespace mo::symbolic::detail {

/// ∂(a^b)/∂b = a^b·log(a) for `power` = a^b, taken as 0 where a = 0 (its
/// limit for b > 0). Without the guard, log(0) makes the product NaN even
/// where the exponent's tangent is 0: a loss (w/w0)^p of the MSL's machines,
/// differentiated along the parameter p by the Jacobian-vector product, at
/// rest.
inline Expr pow_exponent_partial(ExprArena& A, Expr power, Expr base) {
  const Expr zero = A.constant(0);
  return A.select(A.no_event(A.eq(base, zero)), zero, A.mul(power, A.log(base)));
}

}  // namespace mo::symbolic::detail
