// BLT blocks to steps, and zero-crossing collection; see solve.hpp.
#include "solve.hpp"

#include <unordered_map>
#include <unordered_set>

#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/substitute.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic::detail {

namespace {

bool mentions_any(const ExprArena& a, Expr e, const std::unordered_set<Expr, ExprHash>& set) {
  for (Expr l : leaves(a, std::span(&e, 1)))
    if (set.contains(l)) return true;
  return false;
}

/// True for kinds whose value jumps (or is flat) where the operand varies: an
/// equation through which the unknown passes such a node is not affine in it,
/// whatever its derivative says.
bool breaks_affinity(ExprKind k) {
  switch (k) {
    case ExprKind::Lt: case ExprKind::Le: case ExprKind::Gt: case ExprKind::Ge:
    case ExprKind::Eq: case ExprKind::Ne: case ExprKind::Sign: case ExprKind::Floor:
    case ExprKind::Ceil: case ExprKind::ArgList: case ExprKind::External:
      return true;
    case ExprKind::Constant: case ExprKind::Symbol: case ExprKind::Der: case ExprKind::Pre:
    case ExprKind::Delay:
    case ExprKind::Add: case ExprKind::Sub: case ExprKind::Mul: case ExprKind::Div:
    case ExprKind::Neg: case ExprKind::Pow: case ExprKind::Sin: case ExprKind::Cos:
    case ExprKind::Tan: case ExprKind::Asin: case ExprKind::Acos: case ExprKind::Atan:
    case ExprKind::Atan2: case ExprKind::Sinh: case ExprKind::Cosh: case ExprKind::Tanh:
    case ExprKind::Exp: case ExprKind::Log: case ExprKind::Log10: case ExprKind::Sqrt:
    case ExprKind::Abs: case ExprKind::Min: case ExprKind::Max: case ExprKind::Select:
    case ExprKind::And: case ExprKind::Or: case ExprKind::Not: case ExprKind::NoEvent:
    case ExprKind::Smooth:
      return false;
  }
  return false;
}

}  // namespace

bool discontinuous_in(const ExprArena& a, Expr r, std::span<const Expr> vars) {
  const std::unordered_set<Expr, ExprHash> z(vars.begin(), vars.end());
  std::unordered_map<Expr, bool, ExprHash> depends;
  for (Expr e : topological_order(a, std::span(&r, 1))) {
    bool d = z.contains(e);
    if (!a.is_leaf(e))
      for (std::size_t i = 0; i < arity(a.kind(e)); ++i) d = d || depends.at(a.operand(e, i));
    if (d && breaks_affinity(a.kind(e))) return true;
    depends.emplace(e, d);
  }
  return false;
}

Step solve_block(ExprArena& a, const std::vector<Expr>& residuals,
                 const std::vector<Expr>& unknowns, const std::vector<double>& start) {
  const std::unordered_set<Expr, ExprHash> z(unknowns.begin(), unknowns.end());
  ExprMap zero;
  for (Expr u : unknowns) zero[u] = a.constant(0.0);
  EquationBlock b;
  b.unknowns = unknowns;
  b.residuals = residuals;
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    const Expr r = residuals[i];
    const auto used = leaves(a, std::span(&r, 1));
    for (std::size_t j = 0; j < unknowns.size(); ++j) {
      if (std::find(used.begin(), used.end(), unknowns[j]) == used.end()) continue;
      const Expr d = derivative(a, r, unknowns[j]);
      if (a.is_constant(d, 0.0)) continue;
      b.linear = b.linear && !mentions_any(a, d, z);
      b.jacobian.push_back({i, j, d});
    }
    // sign(i), a relation on i: a zero derivative, yet r is not affine and
    // its value at z = 0 is no offset (IdealSwitchWithArc's v - Varc*sign(i)).
    b.linear = b.linear && !discontinuous_in(a, r, unknowns);
  }
  if (b.linear && unknowns.size() == 1 && b.jacobian.size() == 1) {
    const Expr offset = substitute(a, residuals[0], zero);
    return Assignment{unknowns[0], a.div(a.neg(offset), b.jacobian[0].value)};
  }
  if (b.linear)
    for (Expr r : residuals) b.offset.push_back(substitute(a, r, zero));
  else
    b.start = start;
  return b;
}

void collect_zero_crossings(ExprArena& a, const std::vector<Expr>& roots,
                            std::vector<Expr>& out) {
  std::unordered_set<Expr, ExprHash> seen, found(out.begin(), out.end());
  std::vector<Expr> stack(roots.begin(), roots.end());
  while (!stack.empty()) {
    const Expr e = stack.back();
    stack.pop_back();
    if (!seen.insert(e).second) continue;
    const ExprKind k = a.kind(e);
    if (k == ExprKind::NoEvent || a.is_leaf(e) || a.is_constant(e)) continue;
    if (k == ExprKind::Lt || k == ExprKind::Le || k == ExprKind::Gt || k == ExprKind::Ge) {
      const Expr g = a.sub(a.operand(e, 0), a.operand(e, 1));
      if (!a.is_constant(g) && found.insert(g).second) out.push_back(g);
    }
    for (std::size_t i = 0; i < arity(k); ++i) stack.push_back(a.operand(e, i));
  }
}

}  // namespace mo::symbolic::detail
