// Stream connectors (MLS 15). A stream variable (`stream Real h_outflow`)
// is carried by the one flow variable of its connector and gets no
// connection equations of its own. What the connections give are:
//
// - inStream(m_i.c.h) of an inside connector: the mixing value of the other
//   members of its connection set, each weighted by the flow it brings into
//   the set: inside connectors j by max(-m_j, 0), outside connectors k by
//   max(c_k.m_flow, 0) with inStream(c_k.h) as their value (from the set one
//   level up, where c_k is an inside connector);
// - for each outside connector c_q of a set: c_q.h = the same mixing value
//   over the other members.
//
// The spec's recommended forms (MLS 15.2) follow from dropping the members
// that cannot bring flow into the set (m_j.min >= 0 inside, c_k.max <= 0
// outside) and taking a single remaining member's value as it is: an
// unconnected connector's inStream is its own h, a one-to-one connection's
// the other's h, a pass-through c = m gives c.h = m.h and inStream(m.h) =
// inStream(c.h). Two or more members mix, regularised near zero flow as the
// spec requires (unique and continuous in all flows, exact while the flows
// are not all small): with w_j = max(x_j, 0), s = Σ w_j and eps = 1e-5 times
// the smallest nominal of the flows,
//   delta = eps max(1 - s/eps, 0)^2            (C1; 0 from s = eps on)
//   mix = (Σ w_j v_j + delta Σ v_j) / (s + n delta)
// the exact mixing rule while s >= eps, the mean of the members' values v_j
// when all flows vanish. It generates no events (noEvent).
//
// inStream stays a call of its stream variable while equations are
// flattened (the sets are known only once every connect() is) and is
// replaced here, after the connection sets are built.
#include "flattener.hpp"

#include <fmt/format.h>

namespace mo::frontend::detail {

using ast::Expr;
using ast::ExprKind;
using ast::ExprPtr;
using ast::Op;

namespace {

constexpr double kRelativeMixingTolerance = 1e-5;

bool is_in_stream(const Expr &e) {
  return e.kind == ExprKind::Call && e.resolved && e.args.size() == 1 && e.ref.parts.size() == 1 &&
         e.ref.parts[0].name == "inStream";
}

ExprPtr no_event(ExprPtr e, SourceRange r) { return ast::make_call1("noEvent", std::move(e), r); }

ExprPtr positive_part(ExprPtr x, SourceRange r) {
  std::vector<ExprPtr> args;
  args.push_back(std::move(x));
  args.push_back(ast::make_real(0, r));
  return no_event(ast::make_call("max", std::move(args), r), r);
}

ExprPtr add(ExprPtr a, ExprPtr b, SourceRange r) { return ast::make_binary(Op::Add, std::move(a), std::move(b), r); }
ExprPtr mul(ExprPtr a, ExprPtr b, SourceRange r) { return ast::make_binary(Op::Mul, std::move(a), std::move(b), r); }

ExprPtr if_expr(ExprPtr c, ExprPtr a, ExprPtr b, SourceRange r) {
  auto n = std::make_unique<Expr>(ExprKind::If, r);
  n->args.push_back(std::move(c));
  n->args.push_back(std::move(a));
  n->args.push_back(std::move(b));
  return n;
}

/// One member of a mixing: the flow it brings into the set is max(x, 0).
struct Inflow {
  ExprPtr x;     ///< -m_j (inside) or c_k.m_flow (outside)
  ExprPtr value; ///< m_j.h, or inStream(c_k.h)
  double nominal = 1;
};

/// The mixing of `in`, regularised near zero flow (see the top of the file).
ExprPtr mix(std::vector<Inflow> in, SourceRange r) {
  if (in.size() == 1)
    return std::move(in[0].value);
  double nominal = in[0].nominal;
  for (const Inflow &f : in)
    nominal = std::min(nominal, f.nominal);
  const double eps = kRelativeMixingTolerance * nominal;
  auto sum = [&](std::vector<ExprPtr> t) {
    return join_terms(std::move(t), [&](ExprPtr a, ExprPtr b) { return add(std::move(a), std::move(b), r); });
  };
  std::vector<ExprPtr> weights, weighted, values;
  for (Inflow &f : in) {
    ExprPtr w = positive_part(std::move(f.x), r);
    weighted.push_back(mul(w->clone(), f.value->clone(), r));
    weights.push_back(std::move(w));
    values.push_back(std::move(f.value));
  }
  ExprPtr s = sum(std::move(weights));
  // delta = eps max(1 - s/eps, 0)^2: eps at s = 0, 0 from s = eps on, C1.
  ExprPtr gap = ast::make_binary(Op::Sub, ast::make_real(1, r),
                                 ast::make_binary(Op::Div, s->clone(), ast::make_real(eps, r), r), r);
  ExprPtr delta = mul(ast::make_real(eps, r),
                      ast::make_binary(Op::Pow, positive_part(std::move(gap), r), ast::make_real(2, r), r), r);
  const double n = static_cast<double>(in.size());
  ExprPtr num = add(sum(std::move(weighted)), mul(delta->clone(), sum(std::move(values)), r), r);
  ExprPtr den = add(std::move(s), mul(ast::make_real(n, r), std::move(delta), r), r);
  return ast::make_binary(Op::Div, std::move(num), std::move(den), r);
}

/// Every expression slot of `eq` (conditions, both sides, nested bodies).
void expression_slots(ast::Equation &eq, std::vector<ExprPtr *> &out) {
  std::vector<ast::Equation *> eqs{&eq};
  while (!eqs.empty()) {
    ast::Equation *e = eqs.back();
    eqs.pop_back();
    for (ExprPtr *p : {&e->lhs, &e->rhs})
      if (*p) out.push_back(p);
    for (auto &b : e->branches) {
      if (b.condition) out.push_back(&b.condition);
      for (auto &x : b.body) eqs.push_back(&x);
    }
    for (auto &x : e->body) eqs.push_back(&x);
  }
}

} // namespace

std::int32_t Flattener::stream_flow(std::int32_t v, SourceRange where) {
  const auto it = stream_vars_.find(v);
  if (it == stream_vars_.end())
    fail(DiagId::TypeMismatch, where,
         "'" + model_->variables[static_cast<std::size_t>(v)].name + "' is not a stream variable");
  const Instance *c = it->second->parent;
  while (c && !(c->is_connector && c->dims.empty()))
    c = c->parent;
  std::int32_t flow = -1;
  int count = 0;
  if (c)
    for (const auto &m : c->members)
      if (m->is_flow) {
        ++count;
        flow = m->var;
      }
  if (count != 1 || flow < 0)
    fail(DiagId::Unsupported, where,
         fmt::format("stream connector '{}' must have exactly one scalar flow variable (MLS 15.1), it has {}",
                     c ? c->flat : it->second->flat, count));
  return flow;
}

Tensor Flattener::stream_operator(const Expr &call, const Scope &s) {
  const std::string name = call.ref.str();
  if (call.args.size() != 1 || !call.named.empty())
    fail(DiagId::WrongArgumentCount, call.range, name + "() takes one stream variable");
  Tensor t = expr(*call.args[0], s);
  for (ExprPtr &x : t.elems) {
    if (x->kind != ExprKind::Ref || x->var < 0 || !model_->variables[static_cast<std::size_t>(x->var)].is_stream)
      fail(DiagId::TypeMismatch, call.args[0]->range,
           name + "() needs a stream variable of a connector, '" + call.args[0]->ref.str() + "' is not one");
    const std::int32_t v = x->var;
    ExprPtr in = ast::make_call1("inStream", var_ref(*model_, v, call.range), call.range);
    in->resolved = true;
    if (name == "inStream") {
      x = std::move(in);
      continue;
    }
    // actualStream(v) = if m_flow > 0 then inStream(v) else v (MLS 15.3).
    const std::int32_t flow = stream_flow(v, call.range);
    x = if_expr(ast::make_binary(Op::Gt, var_ref(*model_, flow, call.range), ast::make_real(0, call.range), call.range),
                std::move(in), var_ref(*model_, v, call.range), call.range);
  }
  return t;
}

void Flattener::stream_connections(const std::vector<std::vector<std::int32_t>> &sets) {
  // The set of each element (2*var + outside) of a stream variable.
  std::unordered_map<std::int32_t, const std::vector<std::int32_t> *> set_of;
  for (const auto &set : sets)
    if (model_->variables[static_cast<std::size_t>(set[0] / 2)].is_stream)
      for (std::int32_t e : set)
        set_of[e] = &set;
  // A bound of a flow known now: literal, or of parameters fixed already or
  // marked Evaluate = true.
  auto known = [&](const ExprPtr &a) -> std::optional<double> {
    if (!a || !structural(*a))
      return std::nullopt;
    return eval(*a, a->range);
  };
  // The members of element e's set other than e that can bring flow in,
  // with the values they bring (inStream of an outside one: from its own
  // inside element, through `in_stream`).
  std::function<ExprPtr(std::int32_t, SourceRange, int)> in_stream;
  auto inflows = [&](std::int32_t e, SourceRange r, int depth) {
    std::vector<Inflow> in;
    for (std::int32_t k : *set_of.at(e)) {
      if (k == e)
        continue;
      const std::int32_t v = k / 2;
      const bool outside = k % 2 == 1;
      const std::int32_t flow = stream_flow(v, r);
      const flat::Variable &f = model_->variables[static_cast<std::size_t>(flow)];
      const auto bound = known(outside ? f.attr.max : f.attr.min);
      if (bound && (outside ? *bound <= 0 : *bound >= 0))
        continue; // cannot bring flow into the set
      Inflow m;
      m.x = outside ? var_ref(*model_, flow, r) : ast::make_unary(Op::Neg, var_ref(*model_, flow, r), r);
      m.value = outside ? in_stream(2 * v, r, depth + 1) : var_ref(*model_, v, r);
      if (const auto n = known(f.attr.nominal); n && *n > 0)
        m.nominal = *n;
      in.push_back(std::move(m));
    }
    return in;
  };
  in_stream = [&](std::int32_t e, SourceRange r, int depth) -> ExprPtr {
    if (depth > 200)
      fail(DiagId::Unsupported, r, "inStream() of '" + model_->variables[static_cast<std::size_t>(e / 2)].name +
                                       "' nests more than 200 levels of connectors");
    if (!set_of.count(e))
      return var_ref(*model_, e / 2, r); // not connected from outside: its own outflow
    std::vector<Inflow> in = inflows(e, r, depth);
    if (in.empty())
      return var_ref(*model_, e / 2, r);
    return mix(std::move(in), r);
  };
  // Outside connectors: c_q.h = the mixing of the other members.
  for (const auto &set : sets) {
    if (!model_->variables[static_cast<std::size_t>(set[0] / 2)].is_stream)
      continue;
    for (std::int32_t q : set) {
      if (q % 2 == 0)
        continue;
      const SourceRange r = model_->variables[static_cast<std::size_t>(q / 2)].range;
      std::vector<Inflow> in = inflows(q, r, 0);
      ast::Equation eq;
      eq.range = r;
      eq.lhs = var_ref(*model_, q / 2, r);
      eq.rhs = in.empty() ? ast::make_real(0, r) : mix(std::move(in), r);
      model_->equations.push_back(std::move(eq));
    }
  }
  // Every inStream(v) of the model: the value from v's inside element.
  std::vector<ExprPtr *> slots;
  for (auto &eq : model_->equations)
    expression_slots(eq, slots);
  for (auto &eq : model_->initial_equations)
    expression_slots(eq, slots);
  if (model_->optimization) {
    auto &o = *model_->optimization;
    for (ExprPtr *p : {&o.objective, &o.objective_integrand})
      if (*p) slots.push_back(p);
    for (auto &eq : o.constraints)
      expression_slots(eq, slots);
  }
  while (!slots.empty()) {
    ExprPtr *p = slots.back();
    slots.pop_back();
    if (is_in_stream(**p)) {
      const Expr &arg = *(*p)->args[0];
      *p = in_stream(2 * arg.var, (*p)->range, 0);
      continue;
    }
    for (auto &a : (*p)->args)
      if (a) slots.push_back(&a);
  }
}

} // namespace mo::frontend::detail
