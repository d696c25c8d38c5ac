// Helpers shared by the symbolic tests: point evaluation of an expression and
// central finite differences with Richardson extrapolation.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>

#include "mo/symbolic/evaluator.hpp"

namespace mo::symbolic::test {

/// Value of `e` at `values` (leaves missing from `values` throw).
inline double value_at(const ExprArena& arena, Expr e, const LeafValues& values) {
  return evaluate(arena, std::span<const Expr>(&e, 1), values).front();
}

/// d f / d s at s = `at`: central differences at steps h and h/2 combined by
/// Richardson extrapolation; error O(h^4) + rounding, about 1e-10 relative.
inline double finite_difference(const std::function<double(double)>& f, double at) {
  const double h = 1e-3 * std::max(1.0, std::fabs(at));
  const auto central = [&](double step) { return (f(at + step) - f(at - step)) / (2 * step); };
  return (4 * central(h / 2) - central(h)) / 3;
}

/// d e / d leaf at `values`, by finite_difference().
inline double finite_difference(const ExprArena& arena, Expr e, Expr leaf, LeafValues values) {
  const double at = values.at(leaf);
  return finite_difference(
      [&](double s) {
        values[leaf] = s;
        return value_at(arena, e, values);
      },
      at);
}

/// |a - b| <= tolerance * max(1, |a|, |b|): relative, absolute near zero.
inline bool close(double a, double b, double tolerance) {
  return std::fabs(a - b) <= tolerance * std::max({1.0, std::fabs(a), std::fabs(b)});
}

} // namespace mo::symbolic::test
