// Connect semantics (Modelica 3, section 9.2). A connection set holds
// elements (variable, seen from inside or outside): potentials in a set are
// equal; flows sum to zero, inside elements counted +, outside ones −.
// A flow whose inside element is in no set is zero. Stream variables get
// their equations in flatten_stream.cpp.
#include "flattener.hpp"

#include <fmt/format.h>
#include <numeric>

namespace mo::frontend::detail {

using ast::Expr;
using ast::ExprPtr;

namespace {
std::string type_of(const Instance *i) { return i->decl ? i->decl->type.str() : "?"; }

/// The scalar (non-array) instances of `i`: itself, or its array elements.
void scalars(const Instance *i, std::vector<const Instance *> &out) {
  if (i->dims.empty()) {
    out.push_back(i);
    return;
  }
  for (const auto &e : i->elements)
    scalars(e.get(), out);
}
} // namespace

bool Flattener::through_disabled(const ast::ComponentRef &ref, const Scope &s) const {
  if (!s.inst || ref.global)
    return false;
  std::vector<const Instance *> level{s.inst};
  for (const auto &part : ref.parts) {
    std::size_t off = 0;
    for (const Instance *i : level)
      off += disabled_.count({i, part.name});
    if (off > 0)
      return off == level.size(); // every element's is off (else connect() reports the missing one)
    std::vector<const Instance *> next;
    for (const Instance *i : level) {
      const auto it = i->member_index.find(part.name);
      if (it == i->member_index.end())
        return false; // connect() reports it
      scalars(it->second, next);
    }
    level = std::move(next);
  }
  return false;
}

void Flattener::connect(const ast::Equation &eq, const Scope &s, bool graph_only) {
  std::vector<Instance *> side[2];
  std::vector<int> dims[2];
  bool outside[2];
  const Expr *refs[2] = {eq.lhs.get(), eq.rhs.get()};
  for (int k = 0; k < 2; ++k) {
    // A connection to a conditional component that is switched off is removed
    // (4.4.5), also when the component is inside another one or in each
    // element of an array of components (connect(resistor.heatPort, heatPort)).
    if (through_disabled(refs[k]->ref, s))
      return;
    if (!resolve_instances(refs[k]->ref, s, refs[k]->range, dims[k], side[k]))
      fail(DiagId::UnknownComponent, refs[k]->range,
           "unknown connector '" + refs[k]->ref.str() + "' in connect()");
    // Outside: a connector of this class itself; inside: one of a component.
    Instance *first = s.inst->member_index.at(refs[k]->ref.parts[0].name);
    outside[k] = first->is_connector;
    for (Instance *i : side[k])
      if (!i->is_connector)
        fail(DiagId::ConnectNotConnector, refs[k]->range,
             "'" + i->flat + "' is not a connector (its type '" + type_of(i) + "' is not declared 'connector')");
  }
  if (side[0].size() != side[1].size())
    fail(DiagId::ConnectIncompatible, eq.range,
         fmt::format("connect() of {} connector(s) to {}", side[0].size(), side[1].size()));
  if (!graph_only)
    for (const auto &named : side)
      for (const Instance *i : named)
        ++connect_count_[i];
  for (std::size_t i = 0; i < side[0].size(); ++i)
    connect_pair(side[0][i], outside[0], side[1][i], outside[1], eq.range, graph_only);
}

bool Flattener::only_connections(const ast::Equation &eq) {
  if (eq.kind == ast::EquationKind::Connect)
    return true;
  if (eq.kind != ast::EquationKind::For || eq.body.empty())
    return false;
  for (const auto &b : eq.body)
    if (!only_connections(b))
      return false;
  return true;
}

void Flattener::connect_pair(Instance *a, bool a_out, Instance *b, bool b_out, SourceRange where,
                             bool graph_only) {
  // Walk both connector trees in step.
  std::vector<std::pair<Instance *, Instance *>> work{{a, b}};
  while (!work.empty()) {
    auto [x, y] = work.back();
    work.pop_back();
    if (x->var >= 0 || y->var >= 0) {
      if (x->var < 0 || y->var < 0)
        fail(DiagId::ConnectIncompatible, where,
             "cannot connect '" + x->flat + "' to '" + y->flat + "': one is a scalar, the other is not");
      if (x->is_flow != y->is_flow)
        fail(DiagId::ConnectIncompatible, where,
             "cannot connect flow variable '" + (x->is_flow ? x->flat : y->flat) + "' to non-flow variable '" +
                 (x->is_flow ? y->flat : x->flat) + "'");
      if (x->is_stream != y->is_stream)
        fail(DiagId::ConnectIncompatible, where,
             "cannot connect stream variable '" + (x->is_stream ? x->flat : y->flat) + "' to non-stream variable '" +
                 (x->is_stream ? y->flat : x->flat) + "'");
      if (x->causality == ast::Causality::Output && y->causality == ast::Causality::Output && !a_out && !b_out)
        fail(DiagId::ConnectIncompatible, where,
             "cannot connect two outputs '" + x->flat + "' and '" + y->flat + "'");
      if (!graph_only) {
        connections_.emplace_back(2 * x->var + (a_out ? 1 : 0), 2 * y->var + (b_out ? 1 : 0));
        connection_ranges_.push_back(where);
      }
      continue;
    }
    if (x->dims != y->dims)
      fail(DiagId::ConnectIncompatible, where,
           "cannot connect '" + x->flat + "' and '" + y->flat + "': their array sizes differ");
    // An edge of the connection graph too (MLS 9.4); once the graph is
    // closed, a connect inside an if-equation gave its edges already.
    if (!graph_closed_ && is_overdetermined(*x) && is_overdetermined(*y))
      graph_.connections.push_back({x, y, where});
    if (!x->dims.empty()) {
      for (std::size_t i = 0; i < x->elements.size(); ++i)
        work.emplace_back(x->elements[i].get(), y->elements[i].get());
      continue;
    }
    bool same = x->members.size() == y->members.size();
    for (const auto &m : x->members)
      same = same && y->member_index.count(m->name);
    if (!same)
      fail(DiagId::ConnectIncompatible, where,
           "cannot connect '" + x->flat + "' (type '" + type_of(x) + "') to '" + y->flat + "' (type '" + type_of(y) +
               "'): the connectors have different components");
    for (const auto &m : x->members)
      work.emplace_back(m.get(), y->member_index.at(m->name));
  }
}

void Flattener::finish_connections() {
  const std::size_t n = 2 * model_->variables.size();
  std::vector<std::int32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::int32_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  std::vector<char> used(n, 0);
  std::vector<SourceRange> first_range(n);
  const auto broken = broken_connection_pairs();
  for (std::size_t k = 0; k < connections_.size(); ++k) {
    auto [a, b] = connections_[k];
    if (broken.count({a / 2, b / 2})) // a connection that closes a loop: equalityConstraint instead
      continue;
    for (auto e : {a, b})
      if (!used[e]) {
        used[e] = 1;
        first_range[e] = connection_ranges_[k];
      }
    std::int32_t ra = find(a), rb = find(b);
    if (ra != rb)
      parent[std::max(ra, rb)] = std::min(ra, rb);
  }
  // Members of each set, in order of first use (stable output).
  std::vector<std::vector<std::int32_t>> sets(n);
  std::vector<std::int32_t> order;
  for (const auto &[a, b] : connections_)
    for (auto e : {a, b})
      if (used[e] == 1) {
        used[e] = 2;
        std::int32_t r = find(e);
        if (sets[r].empty()) order.push_back(r);
        sets[r].push_back(e);
      }
  auto ref = [&](std::int32_t element, SourceRange r) {
    auto e = ast::make_ref(model_->variables[element / 2].name, r);
    e->var = element / 2;
    return e;
  };
  for (std::int32_t root : order) {
    const auto &set = sets[root];
    SourceRange r = first_range[set[0]];
    const ast::Variability variability = model_->variables[set[0] / 2].variability;
    if (variability == ast::Variability::Parameter || variability == ast::Variability::Constant) {
      // Connected parameters (the phase count m of the MSL's plugs) give no
      // equations: their values must agree (9.2), checked where known.
      const auto &first = model_->variables[set[0] / 2];
      for (std::int32_t e : set) {
        const auto &other = model_->variables[e / 2];
        if (first.value && other.value && *first.value != *other.value)
          diags_.report(DiagId::ConnectIncompatible, r,
                        fmt::format("connected parameters '{}' = {} and '{}' = {} differ", first.name, *first.value,
                                    other.name, *other.value));
      }
      continue;
    }
    if (model_->variables[set[0] / 2].is_stream)
      continue; // stream_connections, once every set is known
    if (model_->variables[set[0] / 2].is_flow) {
      std::vector<ExprPtr> terms;
      for (std::int32_t e : set) {
        ExprPtr term = ref(e, r);
        if (e % 2 == 1) term = ast::make_unary(ast::Op::Neg, std::move(term), r);
        terms.push_back(std::move(term));
      }
      ast::Equation eq;
      eq.range = r;
      eq.lhs = join_terms(std::move(terms), [&](ExprPtr x, ExprPtr y) {
        return ast::make_binary(ast::Op::Add, std::move(x), std::move(y), r);
      });
      eq.rhs = ast::make_real(0, r);
      model_->equations.push_back(std::move(eq));
    } else {
      for (std::size_t i = 1; i < set.size(); ++i) {
        if (set[i] / 2 == set[0] / 2) continue; // the same variable seen from both sides
        ast::Equation eq;
        eq.range = r;
        eq.lhs = ref(set[0], r);
        eq.rhs = ref(set[i], r);
        model_->equations.push_back(std::move(eq));
      }
    }
  }
  equality_constraints();
  // Unconnected flows (inside element in no set) are zero.
  for (std::size_t v = 0; v < model_->variables.size(); ++v) {
    const flat::Variable &var = model_->variables[v];
    if (!var.is_flow || used[2 * v] || var.variability == ast::Variability::Parameter ||
        var.variability == ast::Variability::Constant)
      continue;
    ast::Equation eq;
    eq.range = var.range;
    eq.lhs = ref(static_cast<std::int32_t>(2 * v), var.range);
    eq.rhs = ast::make_real(0, var.range);
    model_->equations.push_back(std::move(eq));
  }
  if (!impure_vars_.empty() && impure_state_.empty())
    diags_.report(DiagId::Unsupported, model_->variables[static_cast<std::size_t>(impure_vars_[0])].range,
                  "the impure random generator is drawn from, but never initialised (initializeImpureRandom)");
  if (!diags_.has_errors()) {
    std::vector<std::vector<std::int32_t>> ordered;
    for (std::int32_t root : order)
      ordered.push_back(std::move(sets[root]));
    try {
      stream_connections(ordered);
    } catch (Reported &) {
      return; // reported (a stream connector without its one flow)
    }
    semilinear_connections(ordered);
    drop_repeated_equations();
    when_assignments_to_reinits();
    mark_free_inputs();
  }
  if (opts_.check_balance && !diags_.has_errors())
    check_balance();
}

} // namespace mo::frontend::detail
