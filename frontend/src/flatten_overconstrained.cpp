// Overdetermined connectors (MLS 9.4): the virtual connection graph of
// Connections.root / potentialRoot / branch and of the connections between
// overdetermined records (those that declare an equalityConstraint
// function, MultiBody's Frames.Orientation), its roots and spanning tree,
// and Connections.isRoot / rooted read from them. The statements, and the
// edges of connect()s inside if-equations, are collected in the connections'
// pass (Flattener::flatten_equations) through if-equations on parameters and
// for-loops; the graph is closed before the other equations, which read it
// (and skip the statements).
//
// The spanning trees take every branch (a required edge, MLS 9.4.2), then the
// connections that join parts not joined yet; each tree has one definite
// root. A connection that closes a loop, or that would join two parts with a
// definite root each, is broken: finish_connections gives it the
// equalityConstraint residues of its two records instead of their equations
// (MLS 9.4.1). A branch that would do either is an error.
#include "flattener.hpp"

#include <deque>
#include <fmt/format.h>

namespace mo::frontend::detail {

using ast::Expr;

namespace {

/// "A.R" of a call's argument, for messages.
std::string arg_text(const Expr &call, std::size_t k) {
  return k < call.args.size() && call.args[k]->kind == ast::ExprKind::Ref ? call.args[k]->ref.str() : "?";
}

} // namespace

bool reads_connection_graph(const Expr &e) {
  std::vector<const Expr *> work{&e};
  while (!work.empty()) {
    const Expr *x = work.back();
    work.pop_back();
    if (x->kind == ast::ExprKind::Call) {
      const std::string n = x->ref.str();
      if (n == "Connections.isRoot" || n == "Connections.rooted" || n == "rooted")
        return true;
    }
    for (const auto &a : x->args)
      if (a)
        work.push_back(a.get());
    for (const auto &na : x->named)
      if (na.value)
        work.push_back(na.value.get());
    for (const auto &row : x->rows)
      for (const auto &a : row)
        if (a)
          work.push_back(a.get());
  }
  return false;
}

bool is_connections_statement(const ast::Equation &eq) {
  if (eq.kind != ast::EquationKind::Call || !eq.lhs)
    return false;
  const std::string n = eq.lhs->ref.str();
  return n == "Connections.root" || n == "Connections.potentialRoot" || n == "Connections.branch";
}

bool Flattener::is_overdetermined(const Instance &x) {
  return x.var < 0 && x.dims.empty() && x.cls && x.cls->def && x.cls->def->restriction == ast::Restriction::Record &&
         find_member_class(x.cls, "equalityConstraint") != nullptr;
}

Instance *Flattener::graph_node(const Expr &call, std::size_t k, const Scope &s) {
  if (k >= call.args.size() || call.args[k]->kind != ast::ExprKind::Ref)
    fail(DiagId::WrongArgumentCount, call.range,
         fmt::format("{}() needs a component as argument {}", call.ref.str(), k + 1));
  std::vector<int> dims;
  std::vector<Instance *> found;
  if (!resolve_instances(call.args[k]->ref, s, call.args[k]->range, dims, found) || found.size() != 1)
    fail(DiagId::UnknownComponent, call.args[k]->range,
         "'" + arg_text(call, k) + "' in " + call.ref.str() + "() is not one component");
  if (!is_overdetermined(*found[0]))
    fail(DiagId::TypeMismatch, call.args[k]->range,
         "'" + arg_text(call, k) + "' in " + call.ref.str() +
             "() is not of an overdetermined type (a record with an equalityConstraint function)");
  return found[0];
}

void Flattener::connections_statement(const ast::Equation &eq, const Scope &s) {
  const Expr &call = *eq.lhs;
  const std::string n = call.ref.str();
  OverconstrainedGraph &g = graph_;
  if (n == "Connections.root") {
    g.roots.push_back(graph_node(call, 0, s));
    g.root_range.emplace(g.roots.back(), eq.range);
  } else if (n == "Connections.potentialRoot") {
    int priority = 0;
    if (call.args.size() > 1)
      priority = static_cast<int>(eval_int(*call.args[1], s));
    for (const auto &na : call.named)
      if (na.name == "priority")
        priority = static_cast<int>(eval_int(*na.value, s));
    g.potential.emplace_back(graph_node(call, 0, s), priority);
  } else {
    Instance *a = graph_node(call, 0, s), *b = graph_node(call, 1, s);
    g.branches.push_back({a, b, eq.range});
  }
}

namespace {

/// A Connections statement, or with `connects` a connect(), in `eq`.
bool contains_graph_statement(const ast::Equation &eq, bool connects = true) {
  if (is_connections_statement(eq) || (connects && eq.kind == ast::EquationKind::Connect))
    return true;
  for (const auto &b : eq.branches)
    for (const auto &x : b.body)
      if (contains_graph_statement(x, connects))
        return true;
  for (const auto &x : eq.body)
    if (contains_graph_statement(x, connects))
      return true;
  return false;
}

} // namespace

void Flattener::collect_graph_statements(const ast::Equation &eq, const Scope &s) {
  if (!contains_graph_statement(eq))
    return;
  if (!graph_probe_ && !contains_graph_statement(eq, false)) {
    // connect()s only: their edges, silently. Flattening the equation later
    // reports what is wrong with it, once.
    const DiagnosticEngine::Mark mark = diags_.mark();
    graph_probe_ = true;
    try {
      collect_graph_statements(eq, s);
    } catch (Reported &) {
    }
    graph_probe_ = false;
    diags_.rollback(mark);
    return;
  }
  if (is_connections_statement(eq)) {
    connections_statement(eq, s);
    return;
  }
  if (eq.kind == ast::EquationKind::Connect) { // its equations come with the if-equation's
    connect(eq, s, true);
    return;
  }
  if (eq.kind == ast::EquationKind::If) {
    for (const auto &b : eq.branches) {
      if (b.condition) {
        ast::ExprPtr c = scalar_expr(*b.condition, s);
        if (!is_constant(*c) && !contains_graph_statement(eq, false))
          return; // connect()s alone: flattening the if-equation reports the condition
        if (!is_constant(*c))
          fail(DiagId::Unsupported, b.condition->range,
               "Connections.root/potentialRoot/branch under a condition that is not a parameter is not supported "
               "(the connection graph is fixed at translation)");
        if (eval(*c, b.condition->range) == 0)
          continue;
      }
      for (const auto &x : b.body)
        collect_graph_statements(x, s);
      return;
    }
    return;
  }
  if (eq.kind == ast::EquationKind::For) {
    for_each_iteration(eq, s, [&](const Scope &inner) {
      for (const auto &b : eq.body)
        collect_graph_statements(b, inner);
    });
    return;
  }
  fail(DiagId::Unsupported, eq.range, "Connections.root/potentialRoot/branch are only supported in if- and for-equations");
}

void Flattener::close_connection_graph() {
  graph_closed_ = true;
  OverconstrainedGraph &g = graph_;
  if (g.roots.empty() && g.potential.empty() && g.branches.empty() && g.connections.empty())
    return;
  // Adjacency of the spanning trees: branches, then the connections that
  // join parts not joined yet (union-find); the others are broken. Each tree
  // has one root (MLS 9.4.2): an edge between two parts that each hold a
  // definite root is broken too (the MSL's QuasiStationary Transformer: a
  // source on each side of the transformer's branches).
  std::unordered_map<Instance *, std::vector<std::pair<Instance *, SourceRange>>> next;
  std::vector<Instance *> nodes; // in order of first appearance: stable messages
  std::unordered_map<Instance *, Instance *> part;
  std::unordered_set<Instance *> rooted_parts; // representatives of parts with a definite root
  const auto find = [&](Instance *x) {
    while (part.at(x) != x) {
      part.at(x) = part.at(part.at(x)); // path halving
      x = part.at(x);
    }
    return x;
  };
  const auto joins = [&](const OverconstrainedGraph::Edge &e) {
    for (Instance *x : {e.a, e.b})
      if (!next.count(x)) {
        nodes.push_back(x);
        next[x];
        part[x] = x;
      }
    Instance *ra = find(e.a), *rb = find(e.b);
    if (ra == rb || (rooted_parts.count(ra) && rooted_parts.count(rb)))
      return false;
    part[ra] = rb;
    if (rooted_parts.erase(ra))
      rooted_parts.insert(rb);
    next[e.a].emplace_back(e.b, e.range);
    next[e.b].emplace_back(e.a, e.range);
    return true;
  };
  for (Instance *root : g.roots)
    if (!part.count(root)) {
      nodes.push_back(root);
      next[root];
      part[root] = root;
      rooted_parts.insert(root);
    }
  for (const auto &e : g.branches)
    if (!joins(e))
      fail(DiagId::Unsupported, e.range,
           find(e.a) == find(e.b)
               ? "this Connections.branch closes a loop of branches ('" + e.a->flat + "' and '" + e.b->flat +
                     "' are joined by branches already); only a connection may close a loop (MLS 9.4.2)"
               : "this Connections.branch joins two definite roots (Connections.root) of the connection graph ('" +
                     e.a->flat + "' and '" + e.b->flat + "' are on their sides); only a connection may be broken "
                     "between them (MLS 9.4.2)");
  for (const auto &e : g.connections)
    if (!joins(e))
      g.broken.push_back(e);
  // Candidate roots in the order MLS 9.4.2 prefers them: definite roots,
  // then potential roots by priority (lowest first), in declaration order.
  std::vector<Instance *> candidates = g.roots;
  std::vector<std::pair<Instance *, int>> potential = g.potential;
  std::stable_sort(potential.begin(), potential.end(), [](const auto &x, const auto &y) { return x.second < y.second; });
  for (const auto &[node, priority] : potential)
    candidates.push_back(node);
  for (Instance *root : candidates) {
    if (g.depth.count(root)) {
      if (std::find(g.roots.begin(), g.roots.end(), root) != g.roots.end() && !g.selected.count(root))
        fail(DiagId::UnbalancedModel, g.root_range.at(root),
             "a second definite root (Connections.root) in a part of the connection graph that has one: '" +
                 root->flat + "'");
      continue;
    }
    g.selected.insert(root);
    std::deque<Instance *> queue{root};
    g.depth[root] = 0;
    std::unordered_map<Instance *, Instance *> from{{root, nullptr}};
    while (!queue.empty()) {
      Instance *x = queue.front();
      queue.pop_front();
      for (const auto &[y, range] : next[x]) {
        if (y == from[x]) {
          from[x] = nullptr; // the tree edge back, once (a double edge is a loop)
          continue;
        }
        g.depth[y] = g.depth[x] + 1;
        from[y] = x;
        queue.push_back(y);
      }
    }
  }
  for (Instance *node : nodes)
    if (!g.depth.count(node))
      fail(DiagId::UnbalancedModel, next[node].front().second,
           "'" + node->flat + "' is in a part of the connection graph without a root (Connections.root or "
           "potentialRoot)");
}

std::set<std::pair<std::int32_t, std::int32_t>> Flattener::broken_connection_pairs() {
  std::set<std::pair<std::int32_t, std::int32_t>> out;
  for (const auto &e : graph_.broken) {
    std::vector<std::pair<Instance *, Instance *>> work{{e.a, e.b}};
    while (!work.empty()) { // both records in step, as connect_pair walked them
      auto [x, y] = work.back();
      work.pop_back();
      if (x->var >= 0 && y->var >= 0) {
        out.insert({x->var, y->var});
        out.insert({y->var, x->var});
        continue;
      }
      for (std::size_t i = 0; i < x->elements.size() && i < y->elements.size(); ++i)
        work.emplace_back(x->elements[i].get(), y->elements[i].get());
      for (const auto &m : x->members)
        if (Instance *other = y->member_index.count(m->name) ? y->member_index.at(m->name) : nullptr)
          work.emplace_back(m.get(), other);
    }
  }
  return out;
}

void Flattener::equality_constraints() {
  for (const auto &e : graph_.broken) {
    try {
      ClassNode *fn = find_member_class(e.a->cls, "equalityConstraint");
      if (!is_record_class(e.a->cls) || !e.a->dims.empty() || !fn)
        fail(DiagId::Unsupported, e.range,
             "this connection of overdetermined connectors ('" + e.a->flat + "' and '" + e.b->flat +
                 "') closes a loop or joins two roots, and their type is not a record with an "
                 "equalityConstraint function: not supported");
      std::vector<Tensor> values;
      values.push_back(record_value({e.a}, {}, e.range));
      values.push_back(record_value({e.b}, {}, e.range));
      const Expr site(ast::ExprKind::Call, e.range);
      std::optional<Tensor> residue = apply_function(fn, std::move(values), site);
      if (!residue || residue->record || residue->dims.size() != 1)
        fail(DiagId::TypeMismatch, e.range,
             "'" + fn->path() + "' does not take the two records of this connection to a vector of residues");
      for (auto &r : residue->elems) {
        ast::Equation eq;
        eq.range = e.range;
        eq.lhs = ast::make_real(0, e.range);
        eq.rhs = std::move(r);
        model_->equations.push_back(std::move(eq));
      }
    } catch (Reported &) {
    }
  }
}

bool Flattener::connections_query(const Expr &call, const Scope &s) {
  const std::string n = call.ref.str();
  if (!graph_closed_)
    fail(DiagId::Unsupported, call.range, n + "() is read before the connection graph is known");
  Instance *a = graph_node(call, 0, s);
  if (n == "Connections.isRoot")
    return graph_.selected.count(a) > 0;
  if (!graph_.depth.count(a))
    throw Reported{}; // the graph has an error, reported when it was closed
  // rooted(A): A nearer a root than B of its branch(A, B) or branch(B, A).
  for (const auto &e : graph_.branches)
    if (e.a == a || e.b == a) {
      Instance *b = e.a == a ? e.b : e.a;
      if (!graph_.depth.count(b))
        throw Reported{};
      return graph_.depth.at(a) < graph_.depth.at(b);
    }
  fail(DiagId::UnbalancedModel, call.range,
       n + "('" + arg_text(call, 0) + "') needs a Connections.branch() with '" + arg_text(call, 0) + "'");
}

} // namespace mo::frontend::detail
