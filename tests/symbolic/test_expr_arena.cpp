// Hash-consing, canonical order, constant folding and the rewrite rules.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/expr_arena.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/substitute.hpp"
#include "mo/symbolic/traversal.hpp"

using namespace mo::symbolic;

namespace {
struct Fixture {
  ExprArena A;
  Expr x = A.symbol("x", SymbolRole::State, 0);
  Expr y = A.symbol("y", SymbolRole::Algebraic, 0);
  Expr p = A.symbol("p", SymbolRole::Parameter, 0);
  Expr c(double v) { return A.constant(v); }
};
} // namespace

TEST_CASE_METHOD(Fixture, "structurally equal expressions are the same node", "[symbolic][arena]") {
  const Expr e1 = A.add(A.sin(x), A.mul(y, p));
  const std::size_t nodes = A.size();
  const Expr e2 = A.add(A.sin(x), A.mul(y, p));
  CHECK(e1 == e2);
  CHECK(A.size() == nodes); // nothing new was created
  CHECK(A.symbol("x", SymbolRole::State, 0) == x);
  CHECK(A.constant(2.5) == A.constant(2.5));
  CHECK(A.der(x) == A.der(x));
  CHECK(A.pre(y) == A.pre(y));
  CHECK(A.der(x) != A.pre(x));
}

TEST_CASE_METHOD(Fixture, "commutative operations have one canonical operand order",
                 "[symbolic][arena]") {
  CHECK(A.add(x, y) == A.add(y, x));
  CHECK(A.mul(x, y) == A.mul(y, x));
  CHECK(A.min(x, y) == A.min(y, x));
  CHECK(A.max(x, y) == A.max(y, x));
  CHECK(A.eq(x, y) == A.eq(y, x));
  CHECK(A.ne(x, y) == A.ne(y, x));
  const Expr a = A.lt(x, y);
  const Expr b = A.gt(p, y);
  CHECK(A.logical_and(a, b) == A.logical_and(b, a));
  CHECK(A.logical_or(a, b) == A.logical_or(b, a));
  // Non-commutative operations keep their order.
  CHECK(A.sub(x, y) != A.sub(y, x));
  CHECK(A.div(x, y) != A.div(y, x));
  CHECK(A.pow(x, y) != A.pow(y, x));
  CHECK(A.lt(x, y) != A.lt(y, x));
  CHECK(A.atan2(x, y) != A.atan2(y, x));
  // Constants go first in products and last in sums.
  CHECK(A.operand(A.mul(x, c(3)), 0) == c(3));
  CHECK(A.operand(A.add(c(3), x), 1) == c(3));
}

TEST_CASE_METHOD(Fixture, "constants are distinct by bit pattern", "[symbolic][arena]") {
  CHECK(A.constant(0.0) != A.constant(-0.0));
  CHECK(A.constant_value(A.constant(-0.0)) == 0.0);
  CHECK(std::signbit(A.constant_value(A.constant(-0.0))));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(A.constant(nan) == A.constant(nan));
}

TEST_CASE_METHOD(Fixture, "constant operands fold", "[symbolic][arena][rewrite]") {
  CHECK(A.add(c(2), c(3)) == c(5));
  CHECK(A.sub(c(2), c(3)) == c(-1));
  CHECK(A.mul(c(2), c(3)) == c(6));
  CHECK(A.div(c(3), c(2)) == c(1.5));
  CHECK(A.neg(c(2)) == c(-2));
  CHECK(A.pow(c(2), c(10)) == c(1024));
  CHECK(A.sin(c(0)) == c(0));
  CHECK(A.exp(c(0)) == c(1));
  CHECK(A.atan2(c(0), c(1)) == c(0));
  CHECK(A.min(c(2), c(3)) == c(2));
  CHECK(A.max(c(2), c(3)) == c(3));
  CHECK(A.floor(c(2.5)) == c(2));
  CHECK(A.ceil(c(2.5)) == c(3));
  CHECK(A.sign(c(-4)) == c(-1));
  CHECK(A.abs(c(-4)) == c(4));
  CHECK(A.lt(c(1), c(2)) == c(1));
  CHECK(A.ge(c(1), c(2)) == c(0));
  CHECK(A.eq(c(2), c(2)) == c(1));
  CHECK(A.ne(c(2), c(2)) == c(0));
  CHECK(A.logical_not(c(0)) == c(1));
  CHECK(A.no_event(c(7)) == c(7));
  CHECK(A.smooth(2, c(7)) == c(7));
  // Folding does what the evaluator does, domain errors included.
  CHECK(std::isnan(A.constant_value(A.sqrt(c(-1)))));
}

TEST_CASE_METHOD(Fixture, "identity rewrites", "[symbolic][arena][rewrite]") {
  CHECK(A.add(x, c(0)) == x);
  CHECK(A.add(c(0), x) == x);
  CHECK(A.sub(x, c(0)) == x);
  CHECK(A.sub(c(0), x) == A.neg(x));
  CHECK(A.mul(x, c(1)) == x);
  CHECK(A.mul(c(1), x) == x);
  CHECK(A.div(x, c(1)) == x);
  CHECK(A.pow(x, c(1)) == x);
  CHECK(A.neg(A.neg(x)) == x);
  CHECK(A.abs(A.abs(x)) == A.abs(x));
  CHECK(A.abs(A.neg(x)) == A.abs(x));
  CHECK(A.floor(A.floor(x)) == A.floor(x));
  CHECK(A.ceil(A.floor(x)) == A.floor(x));
  CHECK(A.no_event(A.no_event(A.sin(x))) == A.no_event(A.sin(x)));
  CHECK(A.no_event(x) == x);
  CHECK(A.smooth(1, x) == x);
  CHECK(A.min(x, x) == x);
  CHECK(A.max(x, x) == x);
}

TEST_CASE_METHOD(Fixture, "rewrites that rely on finite values", "[symbolic][arena][rewrite]") {
  // Finite-value semantics: these may turn NaN or Inf into a finite value.
  CHECK(A.mul(x, c(0)) == c(0));
  CHECK(A.mul(c(0), A.div(c(1), x)) == c(0));
  CHECK(A.div(c(0), x) == c(0));
  CHECK(A.sub(A.sin(x), A.sin(x)) == c(0));
}

TEST_CASE_METHOD(Fixture, "sign and power rewrites", "[symbolic][arena][rewrite]") {
  CHECK(A.mul(x, c(-1)) == A.neg(x));
  CHECK(A.div(x, c(-1)) == A.neg(x));
  CHECK(A.add(x, A.neg(y)) == A.sub(x, y));
  CHECK(A.add(A.neg(y), x) == A.sub(x, y));
  CHECK(A.sub(x, A.neg(y)) == A.add(x, y));
  CHECK(A.add(x, c(-2)) == A.sub(x, c(2)));
  CHECK(A.sub(x, c(-2)) == A.add(x, c(2)));
  CHECK(A.neg(A.sub(x, y)) == A.sub(y, x));
  CHECK(A.mul(A.neg(x), A.neg(y)) == A.mul(x, y));
  CHECK(A.add(x, x) == A.mul(c(2), x));
  CHECK(A.pow(x, c(0)) == c(1));
  CHECK(A.pow(c(1), x) == c(1));
  // pow(x, 2) stays a power; the code generator may square it.
  CHECK(A.kind(A.pow(x, c(2))) == ExprKind::Pow);
}

TEST_CASE_METHOD(Fixture, "conditional and logic rewrites", "[symbolic][arena][rewrite]") {
  const Expr cond = A.lt(x, y);
  CHECK(A.select(c(1), x, y) == x);
  CHECK(A.select(c(0), x, y) == y);
  CHECK(A.select(cond, p, p) == p);
  CHECK(A.kind(A.select(cond, x, y)) == ExprKind::Select);
  CHECK(A.logical_and(c(0), cond) == c(0));
  CHECK(A.logical_and(cond, c(1)) == cond);
  CHECK(A.logical_or(c(1), cond) == c(1));
  CHECK(A.logical_or(cond, c(0)) == cond);
  CHECK(A.logical_and(cond, cond) == cond);
  CHECK(A.logical_or(cond, cond) == cond);
  CHECK(A.logical_not(A.logical_not(cond)) == cond);
}

TEST_CASE_METHOD(Fixture, "make() rebuilds through the factories", "[symbolic][arena]") {
  const Expr ops[] = {x, c(0)};
  CHECK(A.make(ExprKind::Add, ops) == x);
  const Expr smooth_ops[] = {c(2), A.sin(x)};
  CHECK(A.make(ExprKind::Smooth, smooth_ops) == A.smooth(2, A.sin(x)));
  CHECK_THROWS_AS(A.make(ExprKind::Constant, {}), std::invalid_argument);
  CHECK_THROWS_AS(A.make(ExprKind::Add, std::span<const Expr>(ops, 1)), std::invalid_argument);
  const Expr bad_order[] = {x, A.sin(x)};
  CHECK_THROWS_AS(A.make(ExprKind::Smooth, bad_order), std::invalid_argument);
}

TEST_CASE_METHOD(Fixture, "misuse is reported", "[symbolic][arena]") {
  CHECK_THROWS_AS(A.symbol("x", SymbolRole::Parameter, 0), std::invalid_argument);
  CHECK_THROWS_AS(A.symbol("x", SymbolRole::State, 1), std::invalid_argument);
  CHECK_THROWS_AS(A.symbol("", SymbolRole::State, 0), std::invalid_argument);
  CHECK_THROWS_AS(A.der(A.sin(x)), std::invalid_argument);
  CHECK_THROWS_AS(A.pre(c(1)), std::invalid_argument);
  CHECK_THROWS_AS(A.apply(ExprKind::Add, x), std::invalid_argument);
  CHECK_THROWS_AS(A.smooth(-1, A.sin(x)), std::invalid_argument);
  CHECK_THROWS_AS(A.add(x, Expr()), std::out_of_range);
  CHECK_THROWS_AS(A.add(x, Expr(1'000'000)), std::out_of_range);
  CHECK_THROWS_AS(A.constant_value(x), std::invalid_argument);
  CHECK_THROWS_AS(A.symbol_info(c(1)), std::invalid_argument);
  CHECK_THROWS_AS(A.operand(x, 0), std::out_of_range);
}

TEST_CASE_METHOD(Fixture, "symbols keep name, role and index", "[symbolic][arena]") {
  CHECK(A.symbol_info(p).name == "p");
  CHECK(A.symbol_info(p).role == SymbolRole::Parameter);
  CHECK(A.find_symbol("y") == y);
  CHECK_FALSE(A.find_symbol("nope").has_value());
  CHECK(A.symbols().size() == 3);
  CHECK(A.is_leaf(A.der(x)));
  CHECK_FALSE(A.is_leaf(c(1)));
}

TEST_CASE("the kind table matches expr_kinds.def", "[symbolic][arena]") {
  CHECK(expr_kind_count == 45);
  CHECK(arity(ExprKind::Select) == 3);
  CHECK(arity(ExprKind::Atan2) == 2);
  CHECK(kind_name(ExprKind::NoEvent) == "NoEvent");
  CHECK(kind_spelling(ExprKind::Ne) == "<>");
}

TEST_CASE("a provided random generator folds known states and keeps the others", "[symbolic][arena]") {
  ExprArena A;
  const Expr s1 = A.symbol("s1", SymbolRole::Discrete, 0);
  // xorshift64* from {1, 2}: the 64-bit word 2^33 + 1 stepped by hand.
  std::uint64_t w = (std::uint64_t{2} << 32) | 1;
  w ^= w >> 12;
  w ^= w << 25;
  w ^= w >> 27;
  w *= 2685821657736338717ULL;
  const double y = static_cast<double>(static_cast<std::int64_t>(w)) / 18446744073709551616.0 + 0.5;
  const Expr known[] = {A.constant(1), A.constant(2)};
  CHECK(A.is_constant(A.external(100, known), y));
  CHECK(A.is_constant(A.external(101, known), static_cast<double>(static_cast<std::int32_t>(w))));
  CHECK(A.is_constant(A.external(102, known), static_cast<double>(static_cast<std::int32_t>(w >> 32))));
  const Expr varying[] = {s1, A.constant(2)};
  const Expr e = A.external(100, varying);
  CHECK(A.kind(e) == ExprKind::External);
  CHECK(A.external_args(e) == std::vector<Expr>{s1, A.constant(2)});
  CHECK(A.external(100, varying) == e);  // hash-consed
  CHECK(to_modelica(A, e) == "ModelicaRandom_xorshift64star(0, s1, 2)");
  CHECK(evaluate(A, std::span(&e, 1), {{s1, 1.0}})[0] == y);
  CHECK_THROWS_AS(A.external(7, varying), std::invalid_argument);
  // Rebuilt through make(), as substitution does: the same node.
  const Expr ops[] = {A.operand(e, 0), A.operand(e, 1)};
  CHECK(A.make(ExprKind::External, ops) == e);
}

TEST_CASE("delay(): a leaf of the current values whose delay times stay operands", "[symbolic][arena]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  const Expr y = A.symbol("y", SymbolRole::Algebraic, 0);
  const Expr T = A.symbol("T", SymbolRole::Parameter, 0);
  const Expr inner = A.delay(A.mul(x, x), A.constant(0.4), A.constant(0.4));
  const Expr outer = A.delay(A.add(inner, y), T, A.constant(2));
  CHECK(A.is_leaf(outer));
  CHECK(A.delay(A.constant(3), T, T) == A.constant(3));  // a constant is its own past
  CHECK(to_modelica(A, inner) == "delay(x*x, 0.4)");
  CHECK(to_modelica(A, outer) == "delay(y + delay(x*x, 0.4), T, 2)");
  // leaves(): the delay and its delay time, not what it delays.
  const Expr e = A.mul(outer, y);
  CHECK(leaves(A, std::span(&e, 1)) == std::vector<Expr>{y, T, outer});
  CHECK(delay_leaves(A, std::span(&e, 1)) == std::vector<Expr>{inner, outer});
  // At the start time every delay is its expression, nested ones too.
  CHECK(undelayed(A, e) == A.mul(A.add(A.mul(x, x), y), y));
  // Substitution reaches inside the delayed expression (alias elimination).
  const Expr z = A.symbol("z", SymbolRole::Algebraic, 1);
  CHECK(to_modelica(A, substitute(A, outer, ExprMap{{y, z}})) == "delay(delay(x*x, 0.4) + z, T, 2)");
  CHECK(evaluate(A, std::span(&e, 1), {{outer, 2.0}, {y, 3.0}, {T, 1.0}})[0] == 6.0);
}

TEST_CASE("many distinct nodes hash-cons correctly as the table grows", "[symbolic][arena]") {
  ExprArena A;
  const Expr x = A.symbol("x", SymbolRole::State, 0);
  std::vector<Expr> first;
  for (int i = 0; i < 20000; ++i) first.push_back(A.mul(A.constant(i + 2), x));
  const std::size_t nodes = A.size();
  for (int i = 0; i < 20000; ++i) CHECK(A.mul(x, A.constant(i + 2)) == first[i]);
  CHECK(A.size() == nodes);
}
