// Derivatives of every expression kind against finite differences, forward
// against reverse mode, second derivatives, and the size of derivative graphs.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/printer.hpp"
#include "numeric_checks.hpp"

using namespace mo::symbolic;
using mo::symbolic::test::close;
using mo::symbolic::test::finite_difference;
using mo::symbolic::test::value_at;

namespace {

// A test expression for one kind, in two leaves u and v, with the box of
// random test points and some awkward points (zeros, both branches).
struct KindCase {
  Expr f;
  Expr u;
  Expr v;
  double lo = -2;
  double hi = 2;
  std::vector<std::pair<double, double>> awkward;
};

KindCase case_for(ExprArena& A, ExprKind kind) {
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr y = A.symbol("y", SymbolRole::Parameter, 0);
  const Expr xy = A.mul(x, y);
  const auto unary = [&](double lo, double hi) {
    return KindCase{A.apply(kind, xy), x, y, lo, hi, {{0.0, 1.0}, {1.0, 0.0}, {-1.0, 0.5}}};
  };
  const std::vector<std::pair<double, double>> zeros = {{0, 0}, {0, 1}, {-1, 0}, {1, 1}};
  switch (kind) {
  case ExprKind::Constant: return {A.add(A.constant(3), x), x, y, -2, 2, zeros};
  case ExprKind::Symbol: return {x, x, y, -2, 2, zeros};
  case ExprKind::Der: return {A.mul(A.der(x), A.sin(y)), A.der(x), y, -2, 2, zeros};
  case ExprKind::Pre: return {A.mul(A.pre(x), A.cos(y)), A.pre(x), y, -2, 2, zeros};
  case ExprKind::Delay: {  // a recorded value, a leaf as pre() is
    const Expr d = A.delay(A.sin(x), A.constant(1), A.constant(1));
    return {A.mul(d, A.cos(y)), d, y, -2, 2, zeros};
  }
  case ExprKind::Add: return {A.add(A.sin(x), y), x, y, -2, 2, zeros};
  case ExprKind::Sub: return {A.sub(A.sin(x), y), x, y, -2, 2, zeros};
  case ExprKind::Mul: return {A.mul(A.sin(x), y), x, y, -2, 2, zeros};
  case ExprKind::Div: return {A.div(A.sin(x), y), x, y, 0.3, 2, {{0, 1}, {-1, 0.5}}};
  case ExprKind::Neg: return {A.neg(A.sin(xy)), x, y, -2, 2, zeros};
  case ExprKind::Pow: return {A.pow(x, y), x, y, 0.3, 2, {{1, 0}, {0.5, 1}, {2, 2}}};
  case ExprKind::Sin:
  case ExprKind::Cos:
  case ExprKind::Atan:
  case ExprKind::Sinh:
  case ExprKind::Cosh:
  case ExprKind::Tanh:
  case ExprKind::Exp:
  case ExprKind::Abs: return unary(-1.5, 1.5);
  case ExprKind::Tan: return unary(-1, 1);
  case ExprKind::Asin:
  case ExprKind::Acos: return unary(-0.8, 0.8);
  case ExprKind::Log:
  case ExprKind::Log10:
  case ExprKind::Sqrt: return {A.apply(kind, xy), x, y, 0.2, 2, {{1, 1}, {2, 0.25}}};
  // Piecewise constant: derivative 0 away from the jumps.
  case ExprKind::Sign:
  case ExprKind::Floor:
  case ExprKind::Ceil:
    return {A.add(A.apply(kind, xy), x), x, y, -2, 2, {{0.7, 1.3}, {-0.7, 1.3}, {0.5, 0.5}}};
  case ExprKind::Atan2: return {A.atan2(x, y), x, y, -2, 2, {{0, 1}, {1, 0}, {-1, -1}}};
  case ExprKind::Min: return {A.min(A.sin(x), y), x, y, -2, 2, {{0, 1}, {1, 0}}};
  case ExprKind::Max: return {A.max(A.sin(x), y), x, y, -2, 2, {{0, 1}, {1, 0}}};
  case ExprKind::Select:
    return {A.select(A.lt(x, y), A.mul(A.sin(x), y), A.mul(xy, y)), x, y, -2, 2,
            {{0, 1}, {1, 0}, {-1, -0.5}, {0.5, 2}}};
  case ExprKind::Lt:
  case ExprKind::Le:
  case ExprKind::Gt:
  case ExprKind::Ge:
  case ExprKind::Eq:
  case ExprKind::Ne: {
    const Expr ops[] = {x, y};
    return {A.add(A.make(kind, ops), xy), x, y, -2, 2, {{0, 1}, {1, 0}}};
  }
  case ExprKind::And:
  case ExprKind::Or: {
    const Expr ops[] = {A.lt(x, y), A.gt(y, A.constant(0))};
    return {A.add(A.make(kind, ops), xy), x, y, -2, 2, {{0, 1}, {1, -0.5}}};
  }
  case ExprKind::Not: return {A.add(A.logical_not(A.lt(x, y)), xy), x, y, -2, 2, {{0, 1}}};
  case ExprKind::NoEvent:
    return {A.no_event(A.select(A.lt(x, y), A.sin(xy), A.mul(x, x))), x, y, -2, 2,
            {{0, 1}, {1, 0}}};
  case ExprKind::Smooth:
    return {A.smooth(2, A.mul(A.mul(x, x), A.sin(y))), x, y, -2, 2, zeros};
  // A provided random generator of an Integer state: piecewise constant.
  case ExprKind::ArgList:
  case ExprKind::External: {
    const Expr state[] = {A.floor(xy), A.constant(7)};
    return {A.add(A.external(100, state), x), x, y, -2, 2, {{0.7, 1.3}, {-0.7, 1.3}, {0.5, 0.5}}};
  }
  }
  FAIL("no case for kind");
  return {};
}

// True if the two leaves are far enough from any jump or kink of `kind` for
// finite differences with steps up to 2e-3 relative.
bool away_from_jumps(ExprKind kind, double u, double v) {
  const double guard = 4e-2 * std::max({1.0, std::fabs(u), std::fabs(v)});
  const double xy = u * v;
  if (kind == ExprKind::Floor || kind == ExprKind::Ceil || kind == ExprKind::ArgList || kind == ExprKind::External)
    return std::fabs(xy - std::round(xy)) > guard;
  if (kind == ExprKind::Sign || kind == ExprKind::Abs) return std::fabs(xy) > guard;
  if (kind == ExprKind::Min || kind == ExprKind::Max) return std::fabs(std::sin(u) - v) > guard;
  if (kind == ExprKind::Atan2) return u * u + v * v > 0.01 && !(v < 0 && std::fabs(u) < guard);
  // Relations, logic and if-then-else switch where u = v or v = 0.
  return std::fabs(u - v) > guard && std::fabs(v) > guard;
}

// First derivatives by forward and reverse mode against finite differences;
// second derivatives against finite differences of the first, where the first
// derivative is smooth at (u, v).
void check_derivatives(ExprArena& A, ExprKind kind, const KindCase& c, double u, double v,
                       bool check_second) {
  const LeafValues at{{c.u, u}, {c.v, v}};
  const Expr wrt[] = {c.u, c.v};
  const std::vector<Expr> reverse = gradient(A, c.f, wrt);
  for (std::size_t i = 0; i < 2; ++i) {
    const Expr forward = derivative(A, c.f, wrt[i]);
    const double exact = value_at(A, forward, at);
    const double numeric = finite_difference(A, c.f, wrt[i], at);
    INFO(kind_name(kind) << " f = " << to_modelica(A, c.f) << " at (" << u << ", " << v
                         << ") d/d" << to_modelica(A, wrt[i]) << " = "
                         << to_modelica(A, forward));
    CHECK(close(exact, numeric, 1e-7));
    CHECK(close(value_at(A, reverse[i], at), exact, 1e-12));
    // Second derivatives: differentiate the derivative graph again.
    for (std::size_t j = 0; j < 2 && check_second; ++j) {
      const Expr second = derivative(A, forward, wrt[j]);
      const double second_numeric = finite_difference(A, forward, wrt[j], at);
      INFO("second derivative wrt " << to_modelica(A, wrt[j]) << " = "
                                    << to_modelica(A, second));
      CHECK(close(value_at(A, second, at), second_numeric, 1e-6));
    }
  }
}

} // namespace

TEST_CASE("derivatives of every kind match finite differences", "[symbolic][derivative]") {
  std::mt19937 random(20240501);
  for (std::size_t k = 0; k < expr_kind_count; ++k) {
    const auto kind = static_cast<ExprKind>(k);
    ExprArena A;
    const KindCase c = case_for(A, kind);
    std::uniform_real_distribution<double> in_box(c.lo, c.hi);
    int checked = 0;
    for (int attempt = 0; attempt < 200 && checked < 10; ++attempt) {
      const double u = in_box(random);
      const double v = in_box(random);
      if (!away_from_jumps(kind, u, v)) continue;
      check_derivatives(A, kind, c, u, v, true);
      ++checked;
    }
    CHECK(checked == 10);
    // abs has a kink at the awkward points: its first derivative jumps there.
    for (const auto& [u, v] : c.awkward)
      check_derivatives(A, kind, c, u, v, kind != ExprKind::Abs);
  }
}

TEST_CASE("abs has derivative 0 at 0, sign(x) elsewhere", "[symbolic][derivative]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr d = derivative(A, A.abs(x), x);
  CHECK(d == A.sign(x));
  CHECK(value_at(A, d, {{x, 0.0}}) == 0);
  CHECK(value_at(A, d, {{x, -3.0}}) == -1);
}

TEST_CASE("a power's derivative along its exponent is 0, not NaN, where the base is 0", "[symbolic][derivative]") {
  // The MSL's speed-dependent losses (w/w0)^p at rest: the Jacobian-vector
  // product seeds the parameter p too, and a^b*log(a) at a = 0 was NaN.
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr p = A.symbol("p", SymbolRole::Parameter, 0);
  const Expr f = A.pow(x, p);
  const Expr forward = derivative(A, f, p);
  const Expr reverse = gradient(A, f, std::vector<Expr>{x, p})[1];
  for (const Expr d : {forward, reverse}) {
    CHECK(value_at(A, d, {{x, 0.0}, {p, 2.0}}) == 0.0);
    CHECK(value_at(A, d, {{x, 0.5}, {p, 2.0}}) == Approx(0.25 * std::log(0.5)).epsilon(1e-14));
  }
}

TEST_CASE("derivative rules produce the documented forms", "[symbolic][derivative]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr y = A.symbol("y", SymbolRole::State, 1);
  const Expr c = A.lt(x, y);
  CHECK(to_modelica(A, derivative(A, A.select(c, A.sin(x), y), x)) ==
        "if x < y then cos(x) else 0");
  CHECK(to_modelica(A, derivative(A, A.min(x, y), x)) == "if x < y then 1 else 0");
  CHECK(to_modelica(A, derivative(A, A.no_event(A.select(c, A.mul(x, x), y)), x)) ==
        "noEvent(if x < y then 2*x else 0)");
  CHECK(to_modelica(A, derivative(A, A.smooth(2, A.mul(x, A.abs(x))), x)) ==
        "smooth(1, abs(x) + x*sign(x))");
  CHECK(derivative(A, A.floor(x), x) == A.constant(0));
  CHECK(derivative(A, c, x) == A.constant(0));
  CHECK(to_modelica(A, derivative(A, A.pow(x, A.constant(3)), x)) == "3*x^2");
  CHECK(to_modelica(A, derivative(A, A.pow(x, A.constant(2)), x)) == "2*x");
}

TEST_CASE("der(x) and pre(x) are independent of x", "[symbolic][derivative]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  // Nodes are built in separate statements: the order of evaluation of
  // function arguments, and so node ids and printed operand order, is
  // compiler-specific.
  const Expr der_x = A.der(x);
  const Expr pre_x = A.pre(x);
  const Expr e = A.add(A.mul(der_x, x), pre_x);
  CHECK(derivative(A, e, x) == A.der(x));
  CHECK(derivative(A, e, A.der(x)) == x);
  CHECK(derivative(A, e, A.pre(x)) == A.constant(1));
  // A caller seeding der(x) with der(der(x)) as a new symbol: time derivative.
  const Expr dder = A.symbol("der(der(x))", SymbolRole::Derivative, 0);
  const Expr dt = forward_derivative(A, e, ExprMap{{x, A.der(x)}, {A.der(x), dder}});
  CHECK(to_modelica(A, dt) == "der(x)*der(x) + x*der(`der(x)`)");
}

TEST_CASE("forward mode takes directional seeds for many outputs", "[symbolic][derivative]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr y = A.symbol("y", SymbolRole::State, 1);
  const Expr vx = A.symbol("vx", SymbolRole::Algebraic, 0);
  const Expr vy = A.symbol("vy", SymbolRole::Algebraic, 1);
  const Expr outs[] = {A.mul(x, y), A.sin(x), A.constant(4)};
  const auto d = forward_derivative(A, outs, ExprMap{{x, vx}, {y, vy}});
  CHECK(d[0] == A.add(A.mul(vx, y), A.mul(x, vy)));
  CHECK(d[1] == A.mul(A.cos(x), vx));
  CHECK(d[2] == A.constant(0));
  CHECK_THROWS_AS(forward_derivative(A, outs, ExprMap{{A.sin(x), vx}}), std::invalid_argument);
  CHECK_THROWS_AS(gradient(A, outs[0], std::vector<Expr>{x, x}), std::invalid_argument);
  CHECK_THROWS_AS(gradient(A, outs[0], std::vector<Expr>{A.constant(1)}), std::invalid_argument);
}

TEST_CASE("the gradient of a shared graph agrees with forward mode", "[symbolic][derivative]") {
  ExprArena A;
  std::vector<Expr> xs;
  for (int i = 0; i < 6; ++i) xs.push_back(A.symbol("x" + std::to_string(i), SymbolRole::State, i));
  // A graph with heavy sharing and a mix of kinds.
  Expr e = xs[0];
  for (int i = 1; i < 6; ++i) {
    const Expr t = A.add(A.mul(e, xs[i]), A.sin(e));
    e = A.add(A.div(t, A.add(A.constant(2), A.cos(xs[i - 1]))), A.exp(A.neg(A.mul(t, t))));
  }
  const auto reverse = gradient(A, e, xs);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> box(-1, 1);
  for (int trial = 0; trial < 5; ++trial) {
    LeafValues at;
    for (const Expr x : xs) at[x] = box(random);
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const double f = value_at(A, derivative(A, e, xs[i]), at);
      CHECK(close(value_at(A, reverse[i], at), f, 1e-12));
      CHECK(close(f, finite_difference(A, e, xs[i], at), 1e-7));
    }
  }
}

TEST_CASE("derivatives of nested chains have O(N) nodes", "[symbolic][derivative]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  constexpr int N = 2000;
  // Each level uses the previous one twice: a tree of 2^N terms, N nodes.
  Expr e = x;
  for (int i = 0; i < N; ++i) e = A.mul(A.sin(e), A.cos(e));
  const std::size_t before = A.size();
  const Expr d = derivative(A, e, x);
  const std::size_t forward_nodes = A.size() - before;
  CHECK(forward_nodes <= 8 * N);
  const std::size_t before_reverse = A.size();
  const Expr g = gradient(A, e, std::vector<Expr>{x}).front();
  CHECK(A.size() - before_reverse <= 8 * N);
  const LeafValues at{{x, 0.3}};
  CHECK(close(value_at(A, d, at), value_at(A, g, at), 1e-10));
}
