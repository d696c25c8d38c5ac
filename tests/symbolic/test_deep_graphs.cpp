// A 1,000,000-deep chain x_{k+1} = sin(x_k) + 1: printing, evaluation,
// substitution and differentiation must not overflow the stack (the debug
// dump walks the same topological order, so it is not repeated here).
#include <catch2/catch.hpp>

#include <cmath>

#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/substitute.hpp"
#include "mo/symbolic/traversal.hpp"

using namespace mo::symbolic;

TEST_CASE("a million-deep chain is printed, evaluated and differentiated",
          "[symbolic][deep]") {
#if defined(__SANITIZE_ADDRESS__)
  // Still far deeper than any recursion could go on an 8 MiB stack (a
  // recursive walk overflows near 10^5), at a fifth of the sanitized cost.
  constexpr int depth = 200'000;
#else
  constexpr int depth = 1'000'000;
#endif
  ExprArena A;
  const Expr x0 = A.symbol("x0", SymbolRole::State, 0);
  const Expr one = A.constant(1);
  Expr chain = x0;
  for (int k = 0; k < depth; ++k) chain = A.add(A.sin(chain), one);
  CHECK(A.size() == 2 * depth + 2);

  // Reference values in doubles: x_k and d x_k / d x0.
  double value = 0.25, slope = 1;
  for (int k = 0; k < depth; ++k) {
    slope *= std::cos(value);
    value = std::sin(value) + 1;
  }

  const std::string text = to_modelica(A, chain);
  CHECK(text.size() == std::size_t(depth) * 9 + 2);
  CHECK(text.substr(0, 12) == "sin(sin(sin(");
  CHECK(text.substr(text.size() - 10) == ") + 1) + 1");

  CHECK(topological_order(A, std::span<const Expr>(&chain, 1)).size() == 2 * depth + 2);
  const LeafValues at{{x0, 0.25}};
  CHECK(evaluate(A, std::span<const Expr>(&chain, 1), at).front() == Approx(value));

  const Expr forward = derivative(A, chain, x0);
  const Expr reverse = gradient(A, chain, std::vector<Expr>{x0}).front();
  const Expr both[] = {forward, reverse};
  const auto slopes = evaluate(A, both, at);
  CHECK(slopes[0] == Approx(slope).margin(1e-300));
  CHECK(slopes[1] == Approx(slope).margin(1e-300));

  const Expr y = A.symbol("y", SymbolRole::State, 1);
  const Expr renamed = substitute(A, chain, ExprMap{{x0, y}});
  CHECK(evaluate(A, std::span<const Expr>(&renamed, 1), LeafValues{{y, 0.25}}).front() ==
        Approx(value));
}
