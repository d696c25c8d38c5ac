// The cart-pendulum right-hand side of docs/cart-pendulum.md, built with the
// factories: the 2x2 mass-matrix system solved by Cramer's rule. Its
// Jacobians with respect to the states and the parameters, and second
// derivatives, must match finite differences.
#include <catch2/catch.hpp>

#include <array>
#include <random>

#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/jacobian.hpp"
#include "mo/symbolic/printer.hpp"
#include "numeric_checks.hpp"

using namespace mo::symbolic;
using mo::symbolic::test::close;
using mo::symbolic::test::finite_difference;
using mo::symbolic::test::value_at;

namespace {

struct CartPendulum {
  ExprArena A;
  // States x, phi, v = der(x), w = der(phi); input F; parameters p.
  Expr x = A.symbol("x", SymbolRole::State, 0);
  Expr phi = A.symbol("phi", SymbolRole::State, 1);
  Expr v = A.symbol("v", SymbolRole::State, 2);
  Expr w = A.symbol("w", SymbolRole::State, 3);
  Expr F = A.symbol("F", SymbolRole::Input, 0);
  Expr m1 = A.symbol("m1", SymbolRole::Parameter, 0);
  Expr d1 = A.symbol("d1", SymbolRole::Parameter, 1);
  Expr m2 = A.symbol("m2", SymbolRole::Parameter, 2);
  Expr d2 = A.symbol("d2", SymbolRole::Parameter, 3);
  Expr l = A.symbol("l", SymbolRole::Parameter, 4);
  Expr g = A.constant(9.81);
  std::array<Expr, 4> states{x, phi, v, w};
  std::array<Expr, 5> parameters{m1, d1, m2, d2, l};
  std::array<Expr, 4> f; // der(states) = f

  CartPendulum() {
    const Expr half = A.constant(0.5);
    // [a11 a12; a12 a22] [der(v); der(w)] = [b1; b2]
    const Expr a11 = A.add(m1, m2);
    const Expr a12 = A.mul(A.mul(m2, l), A.mul(A.cos(phi), half));
    const Expr a22 = A.div(A.mul(m2, A.pow(l, A.constant(2))), A.constant(3));
    const Expr b1 = A.add(A.sub(A.mul(A.mul(A.mul(m2, l), A.sin(phi)),
                                      A.mul(A.pow(w, A.constant(2)), half)),
                                A.mul(d1, v)),
                          F);
    const Expr b2 = A.sub(A.neg(A.mul(A.mul(A.mul(m2, g), l), A.mul(A.sin(phi), half))),
                          A.mul(d2, w));
    // Cramer's rule.
    const Expr det = A.sub(A.mul(a11, a22), A.mul(a12, a12));
    const Expr dv = A.div(A.sub(A.mul(b1, a22), A.mul(a12, b2)), det);
    const Expr dw = A.div(A.sub(A.mul(a11, b2), A.mul(a12, b1)), det);
    f = {v, w, dv, dw};
  }

  LeafValues point(std::mt19937& random) {
    std::uniform_real_distribution<double> state(-1, 1);
    std::uniform_real_distribution<double> scale(0.8, 1.2);
    return {{x, state(random)},      {phi, 3 * state(random)}, {v, state(random)},
            {w, 2 * state(random)},  {F, 5 * state(random)},   {m1, 2 * scale(random)},
            {d1, 15 * scale(random)}, {m2, scale(random)},     {d2, 0.5 * scale(random)},
            {l, 0.5 * scale(random)}};
  }
};

void check_jacobian(CartPendulum& model, std::span<const Expr> wrt, const LeafValues& at) {
  const SparseJacobian J = jacobian(model.A, model.f, wrt);
  for (std::size_t i = 0; i < model.f.size(); ++i) {
    for (std::size_t j = 0; j < wrt.size(); ++j) {
      const double numeric = finite_difference(model.A, model.f[i], wrt[j], at);
      double exact = 0;
      for (std::size_t k = J.pattern.row_start[i]; k < J.pattern.row_start[i + 1]; ++k)
        if (J.pattern.col[k] == j) exact = value_at(model.A, J.values[k], at);
      INFO("d f[" << i << "] / d " << to_modelica(model.A, wrt[j]));
      CHECK(close(exact, numeric, 1e-7));
    }
  }
}

} // namespace

TEST_CASE("cart-pendulum: the right-hand side matches the mass-matrix solve",
          "[symbolic][cart-pendulum]") {
  CartPendulum model;
  const LeafValues at{{model.x, 0.1}, {model.phi, 0.3}, {model.v, -0.2}, {model.w, 0.4},
                      {model.F, 3.0}, {model.m1, 2.0},  {model.d1, 15.0}, {model.m2, 1.0},
                      {model.d2, 0.5}, {model.l, 0.5}};
  const auto values = evaluate(model.A, model.f, at);
  // The same 2x2 solve in doubles.
  const double c = std::cos(0.3), s = std::sin(0.3);
  const double a11 = 3, a12 = 0.25 * c, a22 = 0.25 / 3;
  const double b1 = 0.5 * s * 0.16 / 2 + 3.0 + 15 * 0.2;
  const double b2 = -9.81 * 0.25 * s - 0.2;
  const double det = a11 * a22 - a12 * a12;
  CHECK(values[0] == -0.2);
  CHECK(values[1] == 0.4);
  CHECK(values[2] == Approx((b1 * a22 - a12 * b2) / det).epsilon(1e-13));
  CHECK(values[3] == Approx((a11 * b2 - a12 * b1) / det).epsilon(1e-13));
}

TEST_CASE("cart-pendulum: df/dx and df/dp match finite differences",
          "[symbolic][cart-pendulum]") {
  CartPendulum model;
  std::mt19937 random(42);
  const SparsityPattern dfdx = jacobian_sparsity(model.A, model.f, model.states);
  // der(x) = v, der(phi) = w; the accelerations depend on phi, v, w but not x.
  CHECK(dfdx.col == std::vector<std::uint32_t>{2, 3, 1, 2, 3, 1, 2, 3});
  for (int trial = 0; trial < 10; ++trial) {
    const LeafValues at = model.point(random);
    check_jacobian(model, model.states, at);
    check_jacobian(model, model.parameters, at);
  }
}

TEST_CASE("cart-pendulum: second derivatives match finite differences of first",
          "[symbolic][cart-pendulum]") {
  CartPendulum model;
  std::mt19937 random(4242);
  std::vector<Expr> wrt(model.states.begin(), model.states.end());
  wrt.insert(wrt.end(), model.parameters.begin(), model.parameters.end());
  for (int trial = 0; trial < 3; ++trial) {
    const LeafValues at = model.point(random);
    for (std::size_t i = 2; i < 4; ++i) {
      const std::vector<Expr> first = gradient(model.A, model.f[i], wrt);
      for (std::size_t a = 0; a < wrt.size(); ++a) {
        // Hessian row by reverse mode over the gradient entry.
        const std::vector<Expr> second = gradient(model.A, first[a], wrt);
        for (std::size_t b = 0; b < wrt.size(); ++b) {
          INFO("d2 f[" << i << "] / d " << to_modelica(model.A, wrt[a]) << " d "
                       << to_modelica(model.A, wrt[b]));
          CHECK(close(value_at(model.A, second[b], at),
                      finite_difference(model.A, first[a], wrt[b], at), 1e-6));
        }
      }
    }
  }
}
