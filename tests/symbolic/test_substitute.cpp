// Substitution of leaves, e.g. for alias elimination.
#include <catch2/catch.hpp>

#include <stdexcept>

#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/substitute.hpp"

using namespace mo::symbolic;

TEST_CASE("symbols are replaced and the result is folded", "[symbolic][substitute]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr y = A.symbol("y", SymbolRole::Algebraic, 0);
  const Expr z = A.symbol("z", SymbolRole::Algebraic, 1);
  const Expr der_x = A.der(x);
  const Expr e = A.add(A.mul(y, A.sin(x)), der_x);
  CHECK(substitute(A, e, ExprMap{{y, A.neg(z)}}) == A.add(A.mul(A.neg(z), A.sin(x)), A.der(x)));
  // Replacing by 0 folds the product away.
  CHECK(substitute(A, e, ExprMap{{y, A.constant(0)}}) == A.der(x));
  // der(x) follows x when x is replaced by another symbol.
  CHECK(to_modelica(A, substitute(A, e, ExprMap{{x, z}})) == "der(z) + y*sin(z)");
  // An expression without the keys is returned unchanged.
  CHECK(substitute(A, A.sin(x), ExprMap{{y, z}}) == A.sin(x));
}

TEST_CASE("substitution is one pass, shared nodes rebuilt once", "[symbolic][substitute]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr y = A.symbol("y", SymbolRole::State, 1);
  const Expr s = A.sin(x);
  const Expr exprs[] = {A.mul(s, s), A.add(s, x)};
  const auto out = substitute(A, exprs, ExprMap{{x, A.add(x, y)}});
  const Expr s2 = A.sin(A.add(x, y));
  CHECK(out[0] == A.mul(s2, s2));
  // The replacement value is not substituted into again.
  CHECK(out[1] == A.add(s2, A.add(x, y)));
}

TEST_CASE("substitution misuse is reported", "[symbolic][substitute]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr y = A.symbol("y", SymbolRole::State, 1);
  const Expr e = A.der(x);
  CHECK_THROWS_AS(substitute(A, e, ExprMap{{x, A.neg(y)}}), std::invalid_argument);
  // ... unless der(x) is replaced too.
  CHECK(substitute(A, e, ExprMap{{x, A.neg(y)}, {A.der(x), A.neg(A.der(y))}}) ==
        A.neg(A.der(y)));
  CHECK_THROWS_AS(substitute(A, e, ExprMap{{A.sin(x), y}}), std::invalid_argument);
}
