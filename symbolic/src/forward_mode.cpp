// Forward-mode differentiation: one pass over the graph in topological order;
// each node's derivative is built from its operands' derivatives.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/traversal.hpp"
#include "node_set.hpp"
#include "pow_rule.hpp"

namespace mo::symbolic {

namespace {

// d e given the operands' derivatives d[0..2]; e is not a leaf or constant,
// and at least one d[i] is nonzero.
Expr forward_rule(ExprArena& A, Expr e, const Expr* x, const Expr* d) {
  const ExprKind k = A.kind(e);
  const Expr zero = A.constant(0);
  const Expr one = A.constant(1);
  switch (k) {
  case ExprKind::Constant:
  case ExprKind::Symbol:
  case ExprKind::Der:
  case ExprKind::Pre:
  case ExprKind::Delay:
    throw std::logic_error("internal error: forward_rule on a leaf");
  case ExprKind::Add: return A.add(d[0], d[1]);
  case ExprKind::Sub: return A.sub(d[0], d[1]);
  case ExprKind::Neg: return A.neg(d[0]);
  case ExprKind::Mul: {
    // Sibling nodes are built in separate statements so that node ids (and
    // so canonical operand order) do not depend on the compiler.
    const Expr left = A.mul(d[0], x[1]);
    return A.add(left, A.mul(x[0], d[1]));
  }
  case ExprKind::Div:
    // d(a/b) = (da - (a/b)*db)/b reuses the quotient node.
    return A.div(A.sub(d[0], A.mul(e, d[1])), x[1]);
  case ExprKind::Pow: {
    // b*a^(b-1)*da + a^b*log(a)*db, each term only when its seed is nonzero,
    // so that x^2 needs no log(x) (undefined for x <= 0); a^b*log(a) is 0 at
    // a = 0 (pow_rule.hpp).
    Expr result = zero;
    if (!A.is_constant(d[0], 0))
      result = A.mul(A.mul(x[1], A.pow(x[0], A.sub(x[1], one))), d[0]);
    if (!A.is_constant(d[1], 0))
      result = A.add(result, A.mul(detail::pow_exponent_partial(A, e, x[0]), d[1]));
    return result;
  }
  case ExprKind::Sin: return A.mul(A.cos(x[0]), d[0]);
  case ExprKind::Cos: return A.neg(A.mul(A.sin(x[0]), d[0]));
  case ExprKind::Tan: return A.mul(A.add(one, A.mul(e, e)), d[0]);
  case ExprKind::Asin: return A.div(d[0], A.sqrt(A.sub(one, A.mul(x[0], x[0]))));
  case ExprKind::Acos: return A.neg(A.div(d[0], A.sqrt(A.sub(one, A.mul(x[0], x[0])))));
  case ExprKind::Atan: return A.div(d[0], A.add(one, A.mul(x[0], x[0])));
  case ExprKind::Atan2: {
    // d atan2(a, b) = (b*da - a*db)/(a^2 + b^2)
    const Expr b_da = A.mul(x[1], d[0]);
    const Expr numerator = A.sub(b_da, A.mul(x[0], d[1]));
    const Expr a_squared = A.mul(x[0], x[0]);
    return A.div(numerator, A.add(a_squared, A.mul(x[1], x[1])));
  }
  case ExprKind::Sinh: return A.mul(A.cosh(x[0]), d[0]);
  case ExprKind::Cosh: return A.mul(A.sinh(x[0]), d[0]);
  case ExprKind::Tanh: return A.mul(A.sub(one, A.mul(e, e)), d[0]);
  case ExprKind::Exp: return A.mul(e, d[0]);
  case ExprKind::Log: return A.div(d[0], x[0]);
  case ExprKind::Log10: return A.div(d[0], A.mul(x[0], A.log(A.constant(10))));
  case ExprKind::Sqrt: return A.div(d[0], A.mul(A.constant(2), e));
  case ExprKind::Abs: return A.mul(A.sign(x[0]), d[0]);
  case ExprKind::Min: return A.select(A.lt(x[0], x[1]), d[0], d[1]);
  case ExprKind::Max: return A.select(A.gt(x[0], x[1]), d[0], d[1]);
  case ExprKind::Select: return A.select(x[0], d[1], d[2]);
  case ExprKind::NoEvent: return A.no_event(d[0]);
  case ExprKind::Smooth: {
    const int order = static_cast<int>(A.constant_value(x[0]));
    return A.smooth(std::max(order - 1, 0), d[1]);
  }
  // Piecewise constant: derivative 0 wherever it exists.
  case ExprKind::Sign:
  case ExprKind::Floor:
  case ExprKind::Ceil:
  case ExprKind::Lt:
  case ExprKind::Le:
  case ExprKind::Gt:
  case ExprKind::Ge:
  case ExprKind::Eq:
  case ExprKind::Ne:
  case ExprKind::And:
  case ExprKind::Or:
  case ExprKind::Not:
  case ExprKind::ArgList:
  case ExprKind::External:
    return zero;
  }
  throw std::logic_error("internal error: forward_rule on unknown kind");
}

} // namespace

std::vector<Expr> forward_derivative(ExprArena& arena, std::span<const Expr> outputs,
                                     const ExprMap& seeds, bool check_seeds) {
  if (check_seeds)
    for (const auto& [leaf, seed] : seeds) {
      if (!arena.is_leaf(leaf))
        throw std::invalid_argument("forward_derivative(): seed key " + to_modelica(arena, leaf) +
                                    " is not a symbol, der() or pre()");
      arena.kind(seed); // throws for a bad handle
    }
  const std::vector<Expr> order = topological_order(arena, outputs);
  const detail::OrderIndex index(order);
  const Expr zero = arena.constant(0);
  std::vector<Expr> d(order.size(), zero);
  Expr x[3];
  Expr dx[3];
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Expr e = order[i];
    if (arena.is_leaf(e)) {
      if (const auto found = seeds.find(e); found != seeds.end()) d[i] = found->second;
      continue;
    }
    const std::size_t n = arity(arena.kind(e));
    bool any_nonzero = false;
    for (std::size_t j = 0; j < n; ++j) {
      x[j] = arena.operand(e, j);
      dx[j] = d[index.position(x[j])];
      any_nonzero = any_nonzero || !arena.is_constant(dx[j], 0);
    }
    // A node whose operands all have derivative 0 has derivative 0.
    if (any_nonzero) d[i] = forward_rule(arena, e, x, dx);
  }
  std::vector<Expr> result;
  result.reserve(outputs.size());
  for (const Expr out : outputs) result.push_back(d[index.position(out)]);
  return result;
}

Expr forward_derivative(ExprArena& arena, Expr output, const ExprMap& seeds) {
  return forward_derivative(arena, std::span<const Expr>(&output, 1), seeds).front();
}

Expr derivative(ExprArena& arena, Expr output, Expr wrt) {
  return forward_derivative(arena, output, ExprMap{{wrt, arena.constant(1)}});
}

} // namespace mo::symbolic
