// The node factories of ExprArena: constant folding, canonical operand order
// for commutative operations, and cheap rewrites. Every rewrite states why it
// is safe under the finite-value semantics described in expr_arena.hpp.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "mo/runtime/modelica_random.hpp"
#include "mo/symbolic/expr_arena.hpp"
#include "scalar_ops.hpp"

namespace mo::symbolic {

namespace {

// True for the one-operand kinds that ExprArena::apply accepts.
bool is_unary_function(ExprKind kind) {
  switch (kind) {
  case ExprKind::Sin:
  case ExprKind::Cos:
  case ExprKind::Tan:
  case ExprKind::Asin:
  case ExprKind::Acos:
  case ExprKind::Atan:
  case ExprKind::Sinh:
  case ExprKind::Cosh:
  case ExprKind::Tanh:
  case ExprKind::Exp:
  case ExprKind::Log:
  case ExprKind::Log10:
  case ExprKind::Sqrt:
  case ExprKind::Abs:
  case ExprKind::Sign:
  case ExprKind::Floor:
  case ExprKind::Ceil:
  case ExprKind::NoEvent:
    return true;
  case ExprKind::Constant:
  case ExprKind::Symbol:
  case ExprKind::Der:
  case ExprKind::Pre:
  case ExprKind::Add:
  case ExprKind::Sub:
  case ExprKind::Mul:
  case ExprKind::Div:
  case ExprKind::Neg:
  case ExprKind::Pow:
  case ExprKind::Atan2:
  case ExprKind::Min:
  case ExprKind::Max:
  case ExprKind::Select:
  case ExprKind::Lt:
  case ExprKind::Le:
  case ExprKind::Gt:
  case ExprKind::Ge:
  case ExprKind::Eq:
  case ExprKind::Ne:
  case ExprKind::And:
  case ExprKind::Or:
  case ExprKind::Not:
  case ExprKind::Smooth:
  case ExprKind::ArgList:
  case ExprKind::External:
  case ExprKind::Delay:
    return false;
  }
  return false;
}

} // namespace

Expr ExprArena::fold_or_intern(ExprKind kind, Expr a, Expr b, Expr c) {
  const Expr operands[3] = {a, b, c};
  double values[3] = {0, 0, 0};
  for (std::size_t i = 0; i < arity(kind); ++i) {
    if (!is_constant(operands[i])) return intern(kind, a, b, c);
    values[i] = constant_value(operands[i]);
  }
  // All operands constant: the same scalar operation the evaluator would do.
  return constant(detail::apply_scalar(kind, values[0], values[1], values[2]));
}

Expr ExprArena::add(Expr a, Expr b) {
  if (is_constant(a) && is_constant(b)) return fold_or_intern(ExprKind::Add, a, b);
  // x + 0 == x exactly, up to the sign of a zero result.
  if (is_constant(a, 0)) return b;
  if (is_constant(b, 0)) return a;
  // x + (-y) == x - y exactly in IEEE arithmetic.
  if (kind(b) == ExprKind::Neg) return sub(a, operand(b, 0));
  if (kind(a) == ExprKind::Neg) return sub(b, operand(a, 0));
  // x + (-c) == x - c exactly; reads better.
  if (is_constant(b) && constant_value(b) < 0) return sub(a, constant(-constant_value(b)));
  if (is_constant(a) && constant_value(a) < 0) return sub(b, constant(-constant_value(a)));
  // x + x == 2*x exactly (doubling is exact).
  if (a == b) return mul(constant(2), a);
  // Canonical order: constant last ("x + 1"), otherwise older node first.
  if (is_constant(a) || (!is_constant(b) && b.id() < a.id())) std::swap(a, b);
  return intern(ExprKind::Add, a, b);
}

Expr ExprArena::sub(Expr a, Expr b) {
  if (is_constant(a) && is_constant(b)) return fold_or_intern(ExprKind::Sub, a, b);
  // x - 0 == x exactly.
  if (is_constant(b, 0)) return a;
  // 0 - x == -x, up to the sign of a zero result.
  if (is_constant(a, 0)) return neg(b);
  // x - x == 0 for every finite x (finite-value semantics).
  if (a == b) return constant(0);
  // x - (-y) == x + y exactly.
  if (kind(b) == ExprKind::Neg) return add(a, operand(b, 0));
  // x - (-c) == x + c exactly.
  if (is_constant(b) && constant_value(b) < 0) return add(a, constant(-constant_value(b)));
  return intern(ExprKind::Sub, a, b);
}

Expr ExprArena::mul(Expr a, Expr b) {
  if (is_constant(a) && is_constant(b)) return fold_or_intern(ExprKind::Mul, a, b);
  // x * 0 == 0 for every finite x (finite-value semantics); keeps
  // derivatives sparse.
  if (is_constant(a, 0) || is_constant(b, 0)) return constant(0);
  // x * 1 == x exactly.
  if (is_constant(a, 1)) return b;
  if (is_constant(b, 1)) return a;
  // x * -1 == -x exactly.
  if (is_constant(a, -1)) return neg(b);
  if (is_constant(b, -1)) return neg(a);
  // (-x) * (-y) == x * y exactly.
  if (kind(a) == ExprKind::Neg && kind(b) == ExprKind::Neg)
    return mul(operand(a, 0), operand(b, 0));
  // Canonical order: constant first ("2*x"), otherwise older node first.
  if (is_constant(b) || (!is_constant(a) && b.id() < a.id())) std::swap(a, b);
  return intern(ExprKind::Mul, a, b);
}

Expr ExprArena::div(Expr a, Expr b) {
  if (is_constant(a) && is_constant(b)) return fold_or_intern(ExprKind::Div, a, b);
  // x / 1 == x exactly.
  if (is_constant(b, 1)) return a;
  // x / -1 == -x exactly.
  if (is_constant(b, -1)) return neg(a);
  // 0 / x == 0 for every x != 0; 0/0 is NaN (finite-value semantics).
  if (is_constant(a, 0)) return constant(0);
  return intern(ExprKind::Div, a, b);
}

Expr ExprArena::neg(Expr a) {
  if (is_constant(a)) return fold_or_intern(ExprKind::Neg, a);
  // -(-x) == x exactly.
  if (kind(a) == ExprKind::Neg) return operand(a, 0);
  // -(x - y) == y - x, up to the sign of a zero result.
  if (kind(a) == ExprKind::Sub) return sub(operand(a, 1), operand(a, 0));
  return intern(ExprKind::Neg, a);
}

Expr ExprArena::pow(Expr a, Expr b) {
  if (is_constant(a) && is_constant(b)) return fold_or_intern(ExprKind::Pow, a, b);
  // pow(x, 1) == x exactly.
  if (is_constant(b, 1)) return a;
  // pow(x, 0) == 1 for every x, NaN included (C and IEEE 754 pow).
  if (is_constant(b, 0)) return constant(1);
  // pow(1, y) == 1 for every y, NaN included (C and IEEE 754 pow).
  if (is_constant(a, 1)) return constant(1);
  return intern(ExprKind::Pow, a, b);
}

Expr ExprArena::apply(ExprKind function, Expr a) {
  if (!is_unary_function(function))
    throw std::invalid_argument("apply() needs a one-operand function kind, not " +
                                std::string(kind_name(function)));
  if (is_constant(a)) return fold_or_intern(function, a);
  const ExprKind inner = kind(a);
  // abs(abs(x)) == abs(x) and abs(-x) == abs(x) exactly.
  if (function == ExprKind::Abs && (inner == ExprKind::Abs || inner == ExprKind::Neg))
    return inner == ExprKind::Abs ? a : apply(ExprKind::Abs, operand(a, 0));
  // floor and ceil are the identity on integer values, which floor/ceil return.
  if ((function == ExprKind::Floor || function == ExprKind::Ceil) &&
      (inner == ExprKind::Floor || inner == ExprKind::Ceil))
    return a;
  // noEvent(noEvent(x)) == noEvent(x); a leaf holds no relation to suppress.
  if (function == ExprKind::NoEvent && (inner == ExprKind::NoEvent || is_leaf(a)))
    return a;
  return intern(function, a);
}

Expr ExprArena::atan2(Expr a, Expr b) { return fold_or_intern(ExprKind::Atan2, a, b); }

Expr ExprArena::min(Expr a, Expr b) {
  // min(x, x) == x exactly.
  if (a == b) return a;
  // Commutative up to which operand a tie returns (equal values anyway).
  if (b.id() < a.id()) std::swap(a, b);
  return fold_or_intern(ExprKind::Min, a, b);
}

Expr ExprArena::max(Expr a, Expr b) {
  // max(x, x) == x exactly.
  if (a == b) return a;
  if (b.id() < a.id()) std::swap(a, b);
  return fold_or_intern(ExprKind::Max, a, b);
}

Expr ExprArena::smooth(int order, Expr a) {
  if (order < 0)
    throw std::invalid_argument("smooth() order must be >= 0, got " + std::to_string(order));
  // A constant or a variable generates no events: smooth() has nothing to say.
  if (is_constant(a) || is_leaf(a)) return a;
  return intern(ExprKind::Smooth, constant(order), a);
}

Expr ExprArena::external(int code, std::span<const Expr> args) {
  if (runtime::modelica_random::generator_of(code) == 0)
    throw std::invalid_argument("external(): no provided function has code " + std::to_string(code));
  std::vector<double> values;
  for (const Expr a : args)
    if (is_constant(a)) values.push_back(constant_value(a));
  // Every argument known: the value the generated code would compute.
  if (values.size() == args.size()) return constant(runtime::modelica_random::value(code, values));
  Expr list = constant(0);
  for (std::size_t i = args.size(); i-- > 0;) list = intern(ExprKind::ArgList, args[i], list);
  return intern(ExprKind::External, constant(code), list);
}

Expr ExprArena::delay(Expr e, Expr delay_time, Expr delay_max) {
  if (is_constant(e)) return e;
  return intern(ExprKind::Delay, e, delay_time, delay_max);
}

std::vector<Expr> ExprArena::external_args(Expr e) const {
  std::vector<Expr> out;
  for (Expr cell = operand(e, 1); kind(cell) == ExprKind::ArgList; cell = operand(cell, 1))
    out.push_back(operand(cell, 0));
  return out;
}

Expr ExprArena::select(Expr condition, Expr a, Expr b) {
  // A constant condition chooses its branch (nonzero is true).
  if (is_constant(condition)) return constant_value(condition) != 0 ? a : b;
  // Equal branches: the value does not depend on the condition.
  if (a == b) return a;
  return intern(ExprKind::Select, condition, a, b);
}

Expr ExprArena::relation(ExprKind kind, Expr a, Expr b) {
  // == and <> are symmetric: canonical order makes a == b and b == a one node.
  if ((kind == ExprKind::Eq || kind == ExprKind::Ne) && b.id() < a.id()) std::swap(a, b);
  return fold_or_intern(kind, a, b);
}

Expr ExprArena::lt(Expr a, Expr b) { return relation(ExprKind::Lt, a, b); }
Expr ExprArena::le(Expr a, Expr b) { return relation(ExprKind::Le, a, b); }
Expr ExprArena::gt(Expr a, Expr b) { return relation(ExprKind::Gt, a, b); }
Expr ExprArena::ge(Expr a, Expr b) { return relation(ExprKind::Ge, a, b); }
Expr ExprArena::eq(Expr a, Expr b) { return relation(ExprKind::Eq, a, b); }
Expr ExprArena::ne(Expr a, Expr b) { return relation(ExprKind::Ne, a, b); }

Expr ExprArena::logical_and(Expr a, Expr b) {
  if (is_constant(b)) std::swap(a, b);
  // false and x == false; true and x == x for Boolean (0/1) x.
  if (is_constant(a)) return constant_value(a) != 0 ? b : constant(0);
  // x and x == x.
  if (a == b) return a;
  if (b.id() < a.id()) std::swap(a, b);
  return intern(ExprKind::And, a, b);
}

Expr ExprArena::logical_or(Expr a, Expr b) {
  if (is_constant(b)) std::swap(a, b);
  // true or x == true; false or x == x for Boolean (0/1) x.
  if (is_constant(a)) return constant_value(a) != 0 ? constant(1) : b;
  // x or x == x.
  if (a == b) return a;
  if (b.id() < a.id()) std::swap(a, b);
  return intern(ExprKind::Or, a, b);
}

Expr ExprArena::logical_not(Expr a) {
  // not not x == x for Boolean (0/1) x.
  if (kind(a) == ExprKind::Not) return operand(a, 0);
  return fold_or_intern(ExprKind::Not, a);
}

Expr ExprArena::make(ExprKind k, std::span<const Expr> ops) {
  if (ops.size() != arity(k))
    throw std::invalid_argument("make(" + std::string(kind_name(k)) + ") needs " +
                                std::to_string(arity(k)) + " operands, got " +
                                std::to_string(ops.size()));
  switch (k) {
  case ExprKind::Constant:
  case ExprKind::Symbol:
    throw std::invalid_argument("make() cannot build a " + std::string(kind_name(k)) +
                                "; use constant() or symbol()");
  case ExprKind::Der: return der(ops[0]);
  case ExprKind::Pre: return pre(ops[0]);
  case ExprKind::Add: return add(ops[0], ops[1]);
  case ExprKind::Sub: return sub(ops[0], ops[1]);
  case ExprKind::Mul: return mul(ops[0], ops[1]);
  case ExprKind::Div: return div(ops[0], ops[1]);
  case ExprKind::Neg: return neg(ops[0]);
  case ExprKind::Pow: return pow(ops[0], ops[1]);
  case ExprKind::Sin:
  case ExprKind::Cos:
  case ExprKind::Tan:
  case ExprKind::Asin:
  case ExprKind::Acos:
  case ExprKind::Atan:
  case ExprKind::Sinh:
  case ExprKind::Cosh:
  case ExprKind::Tanh:
  case ExprKind::Exp:
  case ExprKind::Log:
  case ExprKind::Log10:
  case ExprKind::Sqrt:
  case ExprKind::Abs:
  case ExprKind::Sign:
  case ExprKind::Floor:
  case ExprKind::Ceil:
  case ExprKind::NoEvent:
    return apply(k, ops[0]);
  case ExprKind::Atan2: return atan2(ops[0], ops[1]);
  case ExprKind::Min: return min(ops[0], ops[1]);
  case ExprKind::Max: return max(ops[0], ops[1]);
  case ExprKind::Select: return select(ops[0], ops[1], ops[2]);
  case ExprKind::Lt:
  case ExprKind::Le:
  case ExprKind::Gt:
  case ExprKind::Ge:
  case ExprKind::Eq:
  case ExprKind::Ne:
    return relation(k, ops[0], ops[1]);
  case ExprKind::And: return logical_and(ops[0], ops[1]);
  case ExprKind::Or: return logical_or(ops[0], ops[1]);
  case ExprKind::Not: return logical_not(ops[0]);
  case ExprKind::ArgList: return intern(ExprKind::ArgList, ops[0], ops[1]);
  case ExprKind::Delay: return delay(ops[0], ops[1], ops[2]);
  case ExprKind::External: {
    if (!is_constant(ops[0])) throw std::invalid_argument("external(): the code must be a constant");
    std::vector<Expr> args;
    for (Expr cell = ops[1]; kind(cell) == ExprKind::ArgList; cell = operand(cell, 1)) args.push_back(operand(cell, 0));
    return external(static_cast<int>(constant_value(ops[0])), args);
  }
  case ExprKind::Smooth: {
    const double order = is_constant(ops[0]) ? constant_value(ops[0]) : -1;
    if (order < 0 || order != std::floor(order) || order > 1e6)
      throw std::invalid_argument("smooth() order must be a constant integer >= 0");
    return smooth(static_cast<int>(order), ops[1]);
  }
  }
  throw std::logic_error("internal error: make() on unknown kind");
}

} // namespace mo::symbolic
