// Reverse-mode differentiation: adjoints flow from the output to the leaves in
// reverse topological order; each node passes its adjoint times its local
// partial derivatives on to its operands, where contributions are summed.
#include <stdexcept>
#include <string>

#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/traversal.hpp"
#include "node_set.hpp"
#include "pow_rule.hpp"

namespace mo::symbolic {

namespace {

class AdjointSweep {
public:
  AdjointSweep(ExprArena& arena, const std::vector<Expr>& order, std::vector<bool> active)
      : A(arena), order_(order), index_(order), active_(std::move(active)),
        adjoint_(order.size()) {}

  void seed(Expr e, Expr value) { adjoint_[index_.position(e)] = value; }

  Expr adjoint(Expr e) const {
    if (!index_.contains(e)) return A.constant(0);
    const Expr a = adjoint_[index_.position(e)];
    return a.valid() ? a : A.constant(0);
  }

  void run() {
    for (std::size_t i = order_.size(); i-- > 0;) {
      const Expr e = order_[i];
      if (!adjoint_[i].valid() || !active_[i] || A.is_leaf(e) || A.is_constant(e)) continue;
      propagate(e, adjoint_[i]);
    }
  }

private:
  // Adds contribution() to the adjoint of operand j, if that operand leads to
  // a wrt leaf; the contribution is only built when needed.
  template <class Contribution> void pass(Expr e, std::size_t j, Contribution contribution) {
    const std::size_t p = index_.position(A.operand(e, j));
    if (!active_[p]) return;
    const Expr c = contribution();
    adjoint_[p] = adjoint_[p].valid() ? A.add(adjoint_[p], c) : c;
  }

  void propagate(Expr e, Expr w) {
    const ExprKind k = A.kind(e);
    const std::size_t n = arity(k);
    Expr x[3];
    for (std::size_t j = 0; j < n; ++j) x[j] = A.operand(e, j);
    const Expr zero = A.constant(0);
    const Expr one = A.constant(1);
    switch (k) {
    case ExprKind::Constant:
    case ExprKind::Symbol:
    case ExprKind::Der:
    case ExprKind::Pre:
    case ExprKind::Delay:
      throw std::logic_error("internal error: adjoint propagation from a leaf");
    case ExprKind::Add:
      pass(e, 0, [&] { return w; });
      pass(e, 1, [&] { return w; });
      return;
    case ExprKind::Sub:
      pass(e, 0, [&] { return w; });
      pass(e, 1, [&] { return A.neg(w); });
      return;
    case ExprKind::Neg: pass(e, 0, [&] { return A.neg(w); }); return;
    case ExprKind::Mul:
      pass(e, 0, [&] { return A.mul(w, x[1]); });
      pass(e, 1, [&] { return A.mul(w, x[0]); });
      return;
    case ExprKind::Div:
      // a/b: da gets w/b, db gets -(w/b)*(a/b).
      pass(e, 0, [&] { return A.div(w, x[1]); });
      pass(e, 1, [&] { return A.neg(A.mul(A.div(w, x[1]), e)); });
      return;
    case ExprKind::Pow:
      pass(e, 0, [&] { return A.mul(w, A.mul(x[1], A.pow(x[0], A.sub(x[1], one)))); });
      pass(e, 1, [&] { return A.mul(w, detail::pow_exponent_partial(A, e, x[0])); });
      return;
    case ExprKind::Sin: pass(e, 0, [&] { return A.mul(w, A.cos(x[0])); }); return;
    case ExprKind::Cos: pass(e, 0, [&] { return A.neg(A.mul(w, A.sin(x[0]))); }); return;
    case ExprKind::Tan: pass(e, 0, [&] { return A.mul(w, A.add(one, A.mul(e, e))); }); return;
    case ExprKind::Asin:
      pass(e, 0, [&] { return A.div(w, A.sqrt(A.sub(one, A.mul(x[0], x[0])))); });
      return;
    case ExprKind::Acos:
      pass(e, 0, [&] { return A.neg(A.div(w, A.sqrt(A.sub(one, A.mul(x[0], x[0]))))); });
      return;
    case ExprKind::Atan:
      pass(e, 0, [&] { return A.div(w, A.add(one, A.mul(x[0], x[0]))); });
      return;
    case ExprKind::Atan2: {
      const auto scaled = [&] {
        const Expr a_squared = A.mul(x[0], x[0]); // sequenced: see forward_mode.cpp
        return A.div(w, A.add(a_squared, A.mul(x[1], x[1])));
      };
      pass(e, 0, [&] { return A.mul(scaled(), x[1]); });
      pass(e, 1, [&] { return A.neg(A.mul(scaled(), x[0])); });
      return;
    }
    case ExprKind::Sinh: pass(e, 0, [&] { return A.mul(w, A.cosh(x[0])); }); return;
    case ExprKind::Cosh: pass(e, 0, [&] { return A.mul(w, A.sinh(x[0])); }); return;
    case ExprKind::Tanh: pass(e, 0, [&] { return A.mul(w, A.sub(one, A.mul(e, e))); }); return;
    case ExprKind::Exp: pass(e, 0, [&] { return A.mul(w, e); }); return;
    case ExprKind::Log: pass(e, 0, [&] { return A.div(w, x[0]); }); return;
    case ExprKind::Log10:
      pass(e, 0, [&] { return A.div(w, A.mul(x[0], A.log(A.constant(10)))); });
      return;
    case ExprKind::Sqrt: pass(e, 0, [&] { return A.div(w, A.mul(A.constant(2), e)); }); return;
    case ExprKind::Abs: pass(e, 0, [&] { return A.mul(w, A.sign(x[0])); }); return;
    case ExprKind::Min: {
      const auto first = [&] { return A.lt(x[0], x[1]); };
      pass(e, 0, [&] { return A.select(first(), w, zero); });
      pass(e, 1, [&] { return A.select(first(), zero, w); });
      return;
    }
    case ExprKind::Max: {
      const auto first = [&] { return A.gt(x[0], x[1]); };
      pass(e, 0, [&] { return A.select(first(), w, zero); });
      pass(e, 1, [&] { return A.select(first(), zero, w); });
      return;
    }
    case ExprKind::Select:
      pass(e, 1, [&] { return A.select(x[0], w, zero); });
      pass(e, 2, [&] { return A.select(x[0], zero, w); });
      return;
    // The adjoint passes through; the markers are not carried into the
    // partials of the nodes below (forward mode does carry noEvent).
    case ExprKind::NoEvent: pass(e, 0, [&] { return w; }); return;
    case ExprKind::Smooth: pass(e, 1, [&] { return w; }); return;
    // Piecewise constant: nothing flows back.
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
      return;
    }
    throw std::logic_error("internal error: adjoint propagation of unknown kind");
  }

  ExprArena& A;
  const std::vector<Expr>& order_;
  detail::OrderIndex index_;
  std::vector<bool> active_;
  std::vector<Expr> adjoint_; // invalid = zero so far
};

} // namespace

std::vector<Expr> gradient(ExprArena& arena, Expr output, std::span<const Expr> wrt) {
  detail::NodeSet wanted(wrt.size());
  for (const Expr w : wrt) {
    if (!arena.is_leaf(w))
      throw std::invalid_argument("gradient(): " + to_modelica(arena, w) +
                                  " is not a symbol, der() or pre()");
    if (!wanted.insert(w))
      throw std::invalid_argument("gradient(): " + to_modelica(arena, w) + " appears twice");
  }
  const std::vector<Expr> order = topological_order(arena, std::span<const Expr>(&output, 1));
  const detail::OrderIndex index(order);
  // A node is active if some wrt leaf is below it: only those get adjoints.
  std::vector<bool> active(order.size(), false);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Expr e = order[i];
    if (arena.is_leaf(e)) {
      active[i] = wanted.contains(e);
      continue;
    }
    for (std::size_t j = 0; j < arity(arena.kind(e)) && !active[i]; ++j)
      active[i] = active[index.position(arena.operand(e, j))];
  }
  AdjointSweep sweep(arena, order, std::move(active));
  sweep.seed(output, arena.constant(1));
  sweep.run();
  std::vector<Expr> result;
  result.reserve(wrt.size());
  for (const Expr w : wrt) result.push_back(sweep.adjoint(w));
  return result;
}

} // namespace mo::symbolic
