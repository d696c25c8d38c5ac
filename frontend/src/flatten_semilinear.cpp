// semiLinear() at zero flow (MLS 3.7.2.5, rule 1), on a connection of two
// components whose flows are given by semiLinear of the connected mass flow.
//
// `port.H = semiLinear(port.m, port.h, h)` in both components of a connection
// leaves the port's h undetermined where port.m = 0: every value satisfies
// the equations, and the simulator could only take a least-norm one (h = 0,
// a temperature of 0 K in the MSL's FluidHeatFlow). With x = m1 = -m2 and
// y = H1 = -H2 the two equations read
//   y = semiLinear(x, q2, s);  y = semiLinear(x, s, q1)
// (s the shared port value, q1 and q2 the components' own), which the
// specification recommends replacing by
//   s = if x >= 0 then q2 else q1;  y = semiLinear(x, q2, s)
// Here the first component's equation becomes the one for s; the second one
// and the connection's flow sum give y. Where the shared value is instead the
// negative-flow argument of both (`semiLinear(m, h, port.h)`), the rule gives
// s = if x >= 0 then p1 else p2, with p1 and p2 the components' positive-flow
// arguments. Connections of three or more components, and pass-through
// components without semiLinear between two others, are left as they are.
#include "flattener.hpp"

namespace mo::frontend::detail {

namespace {

using ast::Expr;
using ast::ExprKind;
using ast::Op;

/// `if x >= 0 then kp * x else kn * x` with x a variable (semiLinear's
/// expansion, flatten_expr.cpp; the condition may be in noEvent()).
struct SemiLinear {
  std::int32_t x = -1;
  const Expr *positive = nullptr, *negative = nullptr; ///< kp and kn
  const Expr *condition = nullptr;
};

std::int32_t variable_of(const Expr &e) { return e.kind == ExprKind::Ref ? e.var : -1; }

bool is_zero(const Expr &e) {
  return (e.kind == ExprKind::Real || e.kind == ExprKind::Integer) && e.number == 0.0;
}

/// The factor of `product` other than variable `x`, or null.
const Expr *factor_besides(const Expr &product, std::int32_t x) {
  if (product.kind != ExprKind::Binary || product.op != Op::Mul)
    return nullptr;
  if (variable_of(*product.args[1]) == x)
    return product.args[0].get();
  if (variable_of(*product.args[0]) == x)
    return product.args[1].get();
  return nullptr;
}

std::optional<SemiLinear> semi_linear(const Expr &e) {
  if (e.kind != ExprKind::If || e.args.size() != 3)
    return std::nullopt;
  const Expr *c = &without_no_event(*e.args[0]);
  if (c->kind != ExprKind::Binary || c->op != Op::Ge || !is_zero(*c->args[1]))
    return std::nullopt;
  SemiLinear s;
  s.x = variable_of(*c->args[0]);
  s.condition = e.args[0].get();
  if (s.x < 0)
    return std::nullopt;
  s.positive = factor_besides(*e.args[1], s.x);
  s.negative = factor_besides(*e.args[2], s.x);
  if (!s.positive || !s.negative)
    return std::nullopt;
  return s;
}

/// A flow given by semiLinear: equation `index` reads `flow = semiLinear(...)`.
struct Definition {
  std::size_t index = 0;
  SemiLinear s;
};

} // namespace

void Flattener::semilinear_connections(const std::vector<std::vector<std::int32_t>> &sets) {
  // The connection set of each potential variable, and the partner of each
  // flow variable in a two-member set whose members have the same sign.
  std::map<std::int32_t, std::size_t> potential_set;
  std::map<std::int32_t, std::int32_t> partner;
  std::map<std::int32_t, int> sign;
  std::vector<std::pair<std::int32_t, std::int32_t>> flow_pairs;
  for (std::size_t k = 0; k < sets.size(); ++k) {
    const auto &set = sets[k];
    if (!model_->variables[set[0] / 2].is_flow) {
      for (std::int32_t e : set)
        potential_set.emplace(e / 2, k);
      continue;
    }
    if (set.size() != 2 || set[0] / 2 == set[1] / 2 || set[0] % 2 != set[1] % 2)
      continue;
    const std::int32_t a = set[0] / 2, b = set[1] / 2;
    partner[a] = b, partner[b] = a;
    sign[a] = sign[b] = set[0] % 2;
    flow_pairs.emplace_back(a, b);
  }
  std::map<std::int32_t, Definition> defined;
  for (std::size_t i = 0; i < model_->equations.size(); ++i) {
    const ast::Equation &eq = model_->equations[i];
    if (eq.kind != ast::EquationKind::Simple || !eq.lhs || !eq.rhs)
      continue;
    for (auto [v, e] : {std::pair{eq.lhs.get(), eq.rhs.get()}, std::pair{eq.rhs.get(), eq.lhs.get()}})
      if (std::int32_t y = variable_of(*v); y >= 0 && partner.count(y))
        if (auto s = semi_linear(*e))
          defined.emplace(y, Definition{i, *s});
  }
  auto same_potential = [&](const Expr &a, const Expr &b) {
    const std::int32_t va = variable_of(a), vb = variable_of(b);
    if (va < 0 || vb < 0)
      return false;
    if (va == vb)
      return true;
    auto ia = potential_set.find(va), ib = potential_set.find(vb);
    return ia != potential_set.end() && ib != potential_set.end() && ia->second == ib->second;
  };
  for (const auto &[y1, y2] : flow_pairs) {
    auto d1 = defined.find(y1), d2 = defined.find(y2);
    if (d1 == defined.end() || d2 == defined.end())
      continue;
    const SemiLinear &s1 = d1->second.s, &s2 = d2->second.s;
    // The mass flows are connected to each other as the flows are: x2 = -x1.
    auto p = partner.find(s1.x);
    if (p == partner.end() || p->second != s2.x || sign[s1.x] != sign[y1])
      continue;
    const Expr *shared = nullptr, *if_positive = nullptr, *if_negative = nullptr;
    if (same_potential(*s1.positive, *s2.positive)) // semiLinear(m, port.h, h)
      shared = s1.positive, if_positive = s2.negative, if_negative = s1.negative;
    else if (same_potential(*s1.negative, *s2.negative)) // semiLinear(m, h, port.h)
      shared = s1.negative, if_positive = s1.positive, if_negative = s2.positive;
    else
      continue;
    ast::Equation &eq = model_->equations[d1->second.index];
    auto choice = std::make_unique<Expr>(ExprKind::If, eq.range);
    choice->args.push_back(s1.condition->clone());
    choice->args.push_back(if_positive->clone());
    choice->args.push_back(if_negative->clone());
    ast::ExprPtr target = shared->clone();
    eq.lhs = std::move(target);
    eq.rhs = std::move(choice);
    defined.erase(d1); // each equation once; s1's pointers are not used again
    defined.erase(y2);
  }
}

} // namespace mo::frontend::detail
