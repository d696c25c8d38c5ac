// The numeric meaning of every operator kind on doubles, shared by constant
// folding and the evaluator so that both always agree.
#pragma once

#include "mo/symbolic/expr.hpp"

namespace mo::symbolic::detail {

/// kind(a, b, c) on doubles; unused operands are ignored. Booleans are 0/1;
/// a condition is true when nonzero. Throws std::logic_error for leaf kinds
/// (Constant, Symbol, Der, Pre), which have no operation.
double apply_scalar(ExprKind kind, double a, double b, double c);

} // namespace mo::symbolic::detail
