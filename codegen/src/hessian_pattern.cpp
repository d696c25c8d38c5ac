// Structural pattern of second derivatives; see hessian_pattern.hpp.
#include "hessian_pattern.hpp"

#include <algorithm>
#include <iterator>
#include <unordered_map>

#include "mo/symbolic/traversal.hpp"

namespace mo::codegen::detail {

using symbolic::Expr;
using symbolic::ExprArena;
using symbolic::ExprKind;

namespace {

using Pair = std::pair<int, int>;  // (σ column, τ column)

/// What a node holds in the seeds (see hessian_pattern.hpp). `constant`: the
/// seed-free part may be nonzero.
struct Info {
  bool constant = true;
  std::vector<int> ls, lt;
  std::vector<Pair> p;

  bool seed_free() const { return ls.empty() && lt.empty() && p.empty(); }
  friend bool operator==(const Info&, const Info&) = default;
};

template <class T>
void unite(std::vector<T>& into, const std::vector<T>& other) {
  if (other.empty()) return;
  if (into.empty()) {
    into = other;
    return;
  }
  std::vector<T> out;
  out.reserve(into.size() + other.size());
  std::set_union(into.begin(), into.end(), other.begin(), other.end(), std::back_inserter(out));
  into = std::move(out);
}

void add_products(std::vector<Pair>& p, const std::vector<int>& ls, const std::vector<int>& lt) {
  if (ls.empty() || lt.empty()) return;
  std::vector<Pair> cross;
  cross.reserve(ls.size() * lt.size());
  for (int a : ls)
    for (int b : lt) cross.emplace_back(a, b);  // ascending: ls and lt are
  unite(p, cross);
}

/// Sum, difference, selection: every part of either operand.
Info united(const Info& x, const Info& y) {
  Info out = x;
  out.constant = x.constant || y.constant;
  unite(out.ls, y.ls);
  unite(out.lt, y.lt);
  unite(out.p, y.p);
  return out;
}

/// x · y: the bilinear part gathers σ-linear × τ-linear cross terms.
Info product(const Info& x, const Info& y) {
  Info out;
  out.constant = x.constant && y.constant;
  if (y.constant) out.ls = x.ls, out.lt = x.lt, out.p = x.p;
  if (x.constant) unite(out.ls, y.ls), unite(out.lt, y.lt), unite(out.p, y.p);
  add_products(out.p, x.ls, y.lt);
  add_products(out.p, y.ls, x.lt);
  return out;
}

/// φ(x) for a φ that may be nonlinear in all of x.
Info nonlinear(Info x) {
  x.constant = true;
  add_products(x.p, x.ls, x.lt);
  return x;
}

/// Piecewise constant (relations, sign, floor): no seed dependence.
Info piecewise_constant() { return Info{}; }

class Propagation {
public:
  Propagation(const ExprArena& a, const std::vector<Expr>& sigma, const std::vector<Expr>& tau)
      : a_(a), memo_(a.size(), -1) {
    pool_.emplace_back();  // 0: seed-free, may be nonzero
    Info zero;
    zero.constant = false;
    pool_.push_back(zero);  // 1: structurally zero
    for (std::size_t k = 0; k < sigma.size(); ++k) leaf_[sigma[k]] = store(seed(int(k), true));
    for (std::size_t k = 0; k < tau.size(); ++k) leaf_[tau[k]] = store(seed(int(k), false));
  }

  void step(const symbolic::Step& s) {
    if (const auto* as = std::get_if<symbolic::Assignment>(&s)) {
      leaf_[as->target] = of(as->value);
      return;
    }
    block(std::get<symbolic::EquationBlock>(s));
  }

  const Info& info(Expr e) { return pool_[std::size_t(of(e))]; }

private:
  static Info seed(int column, bool sigma) {
    Info i;
    i.constant = false;
    (sigma ? i.ls : i.lt).push_back(column);
    return i;
  }

  int store(Info i) {
    if (i.seed_free()) return i.constant ? 0 : 1;
    pool_.push_back(std::move(i));
    return int(pool_.size() - 1);
  }

  int leaf(Expr e) const {
    if (auto it = leaf_.find(e); it != leaf_.end()) return it->second;
    return 0;  // neither seed nor target: a value of the point
  }

  /// The node's info, computing the nodes below it not yet known (no recursion).
  int of(Expr root) {
    std::vector<std::pair<Expr, bool>> stack{{root, false}};
    while (!stack.empty()) {
      auto [e, expanded] = stack.back();
      stack.pop_back();
      if (a_.is_leaf(e) || a_.is_constant(e) || memo_[e.id()] >= 0) continue;
      if (expanded) {
        memo_[e.id()] = compute(e);
        continue;
      }
      stack.emplace_back(e, true);
      for (std::size_t i = 0; i < symbolic::arity(a_.kind(e)); ++i) stack.emplace_back(a_.operand(e, i), false);
    }
    return value(root);
  }

  int value(Expr e) const {
    if (a_.is_constant(e)) return a_.constant_value(e) != 0.0 ? 0 : 1;
    if (a_.is_leaf(e)) return leaf(e);
    return memo_[e.id()];
  }

  const Info& operand(Expr e, std::size_t i) const { return pool_[std::size_t(value(a_.operand(e, i)))]; }

  Info all_operands(Expr e) const {
    Info u = operand(e, 0);
    for (std::size_t i = 1; i < symbolic::arity(a_.kind(e)); ++i) u = united(u, operand(e, i));
    return u;
  }

  int compute(Expr e) {
    switch (a_.kind(e)) {
    case ExprKind::Constant:
    case ExprKind::Symbol:
    case ExprKind::Der:
    case ExprKind::Pre:
    case ExprKind::Delay: return value(e);
    case ExprKind::Add:
    case ExprKind::Sub:
    case ExprKind::Neg:
    case ExprKind::Abs:  // piecewise ±x
    case ExprKind::Min:  // piecewise one operand
    case ExprKind::Max:
    case ExprKind::NoEvent:
    case ExprKind::Smooth: return store(all_operands(e));
    case ExprKind::Mul: return store(product(operand(e, 0), operand(e, 1)));
    case ExprKind::Div: {
      const Info& y = operand(e, 1);
      if (y.seed_free()) return store(operand(e, 0));
      return store(product(operand(e, 0), nonlinear(y)));
    }
    case ExprKind::Select: {
      if (operand(e, 0).seed_free()) return store(united(operand(e, 1), operand(e, 2)));
      return store(nonlinear(all_operands(e)));
    }
    case ExprKind::Pow:
    case ExprKind::Sin:
    case ExprKind::Cos:
    case ExprKind::Tan:
    case ExprKind::Asin:
    case ExprKind::Acos:
    case ExprKind::Atan:
    case ExprKind::Atan2:
    case ExprKind::Sinh:
    case ExprKind::Cosh:
    case ExprKind::Tanh:
    case ExprKind::Exp:
    case ExprKind::Log:
    case ExprKind::Log10:
    case ExprKind::Sqrt: return store(nonlinear(all_operands(e)));
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
    case ExprKind::External: return store(piecewise_constant());
    }
    return 0;
  }

  /// Unknowns get the union over the residuals, from structurally zero up to a
  /// fixed point (they appear in the residuals); a nonlinear block's unknowns
  /// may have a nonzero seed-free part.
  void block(const symbolic::EquationBlock& b) {
    const std::vector<Expr> order = symbolic::topological_order(a_, b.residuals);
    std::vector<std::uint8_t> dependent(a_.size(), 0);
    for (Expr z : b.unknowns) dependent[z.id()] = 1, leaf_[z] = 1;
    std::vector<Expr> inner;
    for (Expr e : order) {
      if (a_.is_leaf(e) || a_.is_constant(e)) continue;
      for (std::size_t i = 0; i < symbolic::arity(a_.kind(e)); ++i)
        dependent[e.id()] |= dependent[a_.operand(e, i).id()];
      if (dependent[e.id()]) inner.push_back(e), memo_[e.id()] = -1;
    }
    Info current;
    current.constant = !b.linear;
    for (int round = 0;; ++round) {
      const int unknown = store(current);
      for (Expr z : b.unknowns) leaf_[z] = unknown;
      for (Expr e : inner) memo_[e.id()] = -1;
      Info next = current;
      for (Expr r : b.residuals) next = united(next, info(r));
      next.constant = current.constant || next.constant;
      if (next == current) break;
      current = std::move(next);
    }
  }

  const ExprArena& a_;
  std::vector<int> memo_;  // node id → index into pool_, -1 not computed
  std::vector<Info> pool_;
  std::unordered_map<Expr, int> leaf_;
};

}  // namespace

std::vector<std::vector<std::pair<int, int>>> second_order_pairs(
    const ExprArena& arena, const std::vector<Expr>& sigma, const std::vector<Expr>& tau,
    const std::vector<const std::vector<symbolic::Step>*>& steps, const std::vector<Expr>& rows) {
  Propagation prop(arena, sigma, tau);
  for (const auto* list : steps)
    for (const symbolic::Step& s : *list) prop.step(s);
  std::vector<std::vector<Pair>> out;
  out.reserve(rows.size());
  for (Expr r : rows) {
    out.emplace_back();
    if (!r.valid()) continue;
    for (auto [a, b] : prop.info(r).p) out.back().emplace_back(std::max(a, b), std::min(a, b));
    std::sort(out.back().begin(), out.back().end());
    out.back().erase(std::unique(out.back().begin(), out.back().end()), out.back().end());
  }
  return out;
}

}  // namespace mo::codegen::detail
