// Batch evaluation: shared subexpressions once, Booleans as 0/1, errors.
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>

#include "mo/symbolic/evaluator.hpp"

using namespace mo::symbolic;

TEST_CASE("outputs are evaluated together, sharing subexpressions", "[symbolic][evaluator]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr y = A.symbol("y", SymbolRole::Input, 0);
  const Expr s = A.sin(A.mul(x, y));
  const Expr outs[] = {A.add(s, A.constant(1)), A.mul(s, s), x};
  const Evaluator evaluator(A, outs);
  REQUIRE(evaluator.leaves() == std::vector<Expr>{x, y});
  // x, y, x*y, sin, 1, sin + 1, sin*sin: each node once.
  CHECK(evaluator.instruction_count() == 7);
  CHECK(evaluator.output_count() == 3);
  const std::vector<double> values = evaluator.evaluate(std::vector<double>{0.5, 3.0});
  const double sv = std::sin(1.5);
  CHECK(values[0] == Approx(sv + 1));
  CHECK(values[1] == Approx(sv * sv));
  CHECK(values[2] == 0.5);
  CHECK_THROWS_AS(evaluator.evaluate(std::vector<double>{1.0}), std::invalid_argument);
}

TEST_CASE("relations and logic evaluate to 0 and 1", "[symbolic][evaluator]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr y = A.symbol("y", SymbolRole::State, 1);
  const Expr outs[] = {A.lt(x, y), A.le(x, y), A.gt(x, y), A.ge(x, y), A.eq(x, y),
                       A.ne(x, y), A.logical_and(A.lt(x, y), A.gt(y, A.constant(0))),
                       A.logical_or(A.gt(x, y), A.lt(y, A.constant(0))),
                       A.logical_not(A.lt(x, y)),
                       A.select(A.lt(x, y), A.constant(10), A.constant(20))};
  const std::vector<double> at = evaluate(A, outs, LeafValues{{x, 1.0}, {y, 2.0}});
  CHECK(at == std::vector<double>{1, 1, 0, 0, 0, 1, 1, 0, 0, 10});
  const std::vector<double> tie = evaluate(A, outs, LeafValues{{x, 2.0}, {y, 2.0}});
  CHECK(tie == std::vector<double>{0, 1, 0, 1, 1, 0, 0, 0, 1, 20});
}

TEST_CASE("der and pre are leaves with values of their own", "[symbolic][evaluator]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr e = A.add(A.der(x), A.mul(A.constant(2), A.pre(x)));
  // x itself is not needed: only der(x) and pre(x) appear.
  CHECK(evaluate(A, std::span<const Expr>(&e, 1), LeafValues{{A.der(x), 1.0}, {A.pre(x), 3.0}})
            .front() == 7.0);
}

TEST_CASE("built-in functions follow Modelica", "[symbolic][evaluator]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr outs[] = {A.sign(x), A.floor(x), A.ceil(x), A.abs(x), A.min(x, A.constant(-3)),
                       A.max(x, A.constant(-3)), A.log10(A.neg(x)), A.smooth(1, A.exp(x)),
                       A.no_event(A.lt(x, A.constant(0)))};
  const auto v = evaluate(A, outs, LeafValues{{x, -2.5}});
  CHECK(v[0] == -1);
  CHECK(v[1] == -3);
  CHECK(v[2] == -2);
  CHECK(v[3] == 2.5);
  CHECK(v[4] == -3);
  CHECK(v[5] == -2.5);
  CHECK(v[6] == Approx(std::log10(2.5)));
  CHECK(v[7] == Approx(std::exp(-2.5)));
  CHECK(v[8] == 1);
  CHECK(evaluate(A, outs, LeafValues{{x, 0.0}})[0] == 0);
}

TEST_CASE("a missing leaf value is reported by name", "[symbolic][evaluator]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr y = A.symbol("pendulum.phi", SymbolRole::State, 1);
  const Expr e = A.add(x, y);
  CHECK_THROWS_WITH(evaluate(A, std::span<const Expr>(&e, 1), LeafValues{{x, 1.0}}),
                    Catch::Contains("pendulum.phi"));
}
