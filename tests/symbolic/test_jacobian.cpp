// Jacobian structure from dependency analysis, and values against gradients.
#include <catch2/catch.hpp>

#include <stdexcept>

#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/jacobian.hpp"

using namespace mo::symbolic;

TEST_CASE("the Jacobian has entries only where outputs depend on leaves",
          "[symbolic][jacobian]") {
  ExprArena A;
  const Expr x0 = A.symbol("x0", SymbolRole::State, 0);
  const Expr x1 = A.symbol("x1", SymbolRole::State, 1);
  const Expr x2 = A.symbol("x2", SymbolRole::State, 2);
  const Expr p = A.symbol("p", SymbolRole::Parameter, 0);
  const Expr outs[] = {
      A.mul(p, x0),                          // row 0: x0 (and p, not in wrt)
      A.add(A.sin(x2), A.mul(x0, x0)),       // row 1: x0, x2
      A.constant(5),                         // row 2: nothing
      A.add(A.floor(x1), x2),                // row 3: x1 structurally, x2
  };
  const Expr wrt[] = {x0, x1, x2};
  const SparsityPattern structure = jacobian_sparsity(A, outs, wrt);
  CHECK(structure.rows == 4);
  CHECK(structure.cols == 3);
  CHECK(structure.row_start == std::vector<std::size_t>{0, 1, 3, 3, 5});
  CHECK(structure.col == std::vector<std::uint32_t>{0, 0, 2, 1, 2});
  CHECK(structure.contains(1, 2));
  CHECK_FALSE(structure.contains(1, 1));
  CHECK_THROWS_AS(structure.contains(4, 0), std::out_of_range);

  const SparseJacobian J = jacobian(A, outs, wrt);
  // d floor(x1)/d x1 folds to 0, so that entry is dropped from the values.
  CHECK(J.pattern.row_start == std::vector<std::size_t>{0, 1, 3, 3, 4});
  CHECK(J.pattern.col == std::vector<std::uint32_t>{0, 0, 2, 2});
  CHECK(J.values == std::vector<Expr>{p, A.mul(A.constant(2), x0), A.cos(x2), A.constant(1)});
  CHECK(J.pattern.nonzeros() == J.values.size());
}

TEST_CASE("der(x) columns are separate from x columns", "[symbolic][jacobian]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr y = A.symbol("y", SymbolRole::Algebraic, 0);
  // Residual of a DAE: 0 = der(x) - y, 0 = y - x^2.
  const Expr residuals[] = {A.sub(A.der(x), y), A.sub(y, A.pow(x, A.constant(2)))};
  const Expr wrt[] = {A.der(x), x, y};
  const SparseJacobian J = jacobian(A, residuals, wrt);
  CHECK(J.pattern.col == std::vector<std::uint32_t>{0, 2, 1, 2});
  CHECK(J.values == std::vector<Expr>{A.constant(1), A.constant(-1),
                                      A.neg(A.mul(A.constant(2), x)), A.constant(1)});
  const Expr twice[] = {x, x};
  CHECK_THROWS_AS(jacobian(A, residuals, twice), std::invalid_argument);
}
