// Inputs the equations leave free (issue 10, Xcos dialect): in a file Xcos
// writes, `input Real `InPutPort1.vi`` is driven by a non-Modelica block of the
// diagram and no equation of the model defines it. Which inputs are free is a
// structural decision: a maximum matching of equations to the unknowns that
// are not inputs, then augmented with the inputs; an input the augmented
// matching leaves unmatched is not needed by any equation and becomes an
// input of the model (known, not solved for).
//
// Also here: `v = e` in a when-clause where v is differentiated elsewhere
// (Xcos writes `der(T0) = 0.` and `when ... then T0 = time;`) is reinit(v, e).
//
// The rows of the matching are the scalar equations of the balance count
// (flat::equation_count), with the when-clause rule of balance_rows().
#include "flattener.hpp"

#include <functional>

#include <algorithm>
#include <deque>
#include <set>

namespace mo::frontend::detail {

namespace {

/// Maximum bipartite matching by breadth-first augmenting paths (no
/// recursion). rows[r] lists the columns row r may take.
class Matching {
public:
  Matching(const std::vector<std::vector<std::int32_t>> &rows, std::size_t columns)
      : rows_(rows), row_of_(columns, -1), col_of_(rows.size(), -1) {}

  /// Tries to match row r through an augmenting path over columns `allowed`.
  bool augment(std::size_t r, const std::vector<char> &allowed) {
    std::vector<std::int32_t> parent_row(row_of_.size(), -2);  // column → row that reached it
    std::deque<std::int32_t> queue{static_cast<std::int32_t>(r)};
    while (!queue.empty()) {
      const std::int32_t row = queue.front();
      queue.pop_front();
      for (std::int32_t c : rows_[static_cast<std::size_t>(row)]) {
        if (!allowed[static_cast<std::size_t>(c)] || parent_row[static_cast<std::size_t>(c)] != -2) continue;
        parent_row[static_cast<std::size_t>(c)] = row;
        if (row_of_[static_cast<std::size_t>(c)] < 0) {
          flip(c, parent_row);
          return true;
        }
        queue.push_back(row_of_[static_cast<std::size_t>(c)]);
      }
    }
    return false;
  }

  [[nodiscard]] bool row_matched(std::size_t r) const { return col_of_[r] >= 0; }
  [[nodiscard]] bool column_matched(std::size_t c) const { return row_of_[c] >= 0; }

private:
  void flip(std::int32_t c, const std::vector<std::int32_t> &parent_row) {
    while (c >= 0) {
      const std::int32_t row = parent_row[static_cast<std::size_t>(c)];
      const std::int32_t previous = col_of_[static_cast<std::size_t>(row)];
      col_of_[static_cast<std::size_t>(row)] = c;
      row_of_[static_cast<std::size_t>(c)] = row;
      c = previous;
    }
  }

  const std::vector<std::vector<std::int32_t>> &rows_;
  std::vector<std::int32_t> row_of_, col_of_;
};

} // namespace

std::vector<std::vector<std::int32_t>> balance_rows(const flat::Model &m) {
  std::vector<std::vector<std::int32_t>> rows;
  std::set<std::int32_t> when_assigned;
  // What a when-branch assigns: `v = e`, `(a, b) = f(...)`, and the same
  // through the branches of an if-equation inside it (the MSL's
  // CombiTimeTable: `if next < DBL_MAX then nextTimeEvent = ... else ...`).
  std::function<void(const std::vector<ast::Equation> &)> assigned = [&](const std::vector<ast::Equation> &body) {
    for (const auto &s : body) {
      if (s.kind == ast::EquationKind::If) {
        for (const auto &branch : s.branches)
          assigned(branch.body);
        continue;
      }
      if (s.kind != ast::EquationKind::Simple || !s.lhs)
        continue;
      std::vector<const ast::Expr *> targets{s.lhs.get()};
      if (s.lhs->kind == ast::ExprKind::Tuple) {
        targets.clear();
        for (const auto &a : s.lhs->args)
          if (a) targets.push_back(a.get());
      }
      for (const ast::Expr *t : targets)
        if (t->kind == ast::ExprKind::Ref && t->var >= 0 && when_assigned.insert(t->var).second)
          rows.push_back({t->var});
    }
  };
  for (const auto &eq : m.equations) {
    if (eq.kind == ast::EquationKind::When) {
      for (const auto &branch : eq.branches)
        assigned(branch.body);
      continue;
    }
    const std::size_t n = flat::equation_count(eq);
    if (n == 0) continue;
    std::vector<std::int32_t> vars;
    equation_uses(eq, vars);
    std::sort(vars.begin(), vars.end());
    vars.erase(std::unique(vars.begin(), vars.end()), vars.end());
    std::erase_if(vars, [&](std::int32_t v) { return !m.variables[static_cast<std::size_t>(v)].is_unknown(); });
    for (std::size_t k = 0; k < n; ++k) rows.push_back(vars);
  }
  return rows;
}

namespace {

/// Variables that appear as der(v) in the equations (when bodies excluded).
std::vector<char> differentiated(const flat::Model &m) {
  std::vector<char> out(m.variables.size(), 0);
  std::vector<const ast::Expr *> work;
  for (const auto &eq : m.equations) {
    if (eq.kind == ast::EquationKind::When) continue;
    std::vector<const ast::Equation *> eqs{&eq};
    while (!eqs.empty()) {
      const ast::Equation *e = eqs.back();
      eqs.pop_back();
      if (e->lhs) work.push_back(e->lhs.get());
      if (e->rhs) work.push_back(e->rhs.get());
      for (const auto &b : e->branches)
        for (const auto &x : b.body) eqs.push_back(&x);
    }
  }
  while (!work.empty()) {
    const ast::Expr *x = work.back();
    work.pop_back();
    if (x->kind == ast::ExprKind::Call && x->ref.str() == "der" && x->args.size() == 1 && x->args[0] &&
        x->args[0]->kind == ast::ExprKind::Ref && x->args[0]->var >= 0)
      out[static_cast<std::size_t>(x->args[0]->var)] = 1;
    for (const auto &a : x->args)
      if (a) work.push_back(a.get());
  }
  return out;
}

} // namespace

void Flattener::when_assignments_to_reinits() {
  const std::vector<char> der = differentiated(*model_);
  for (auto &eq : model_->equations) {
    if (eq.kind != ast::EquationKind::When) continue;
    for (auto &branch : eq.branches)
      for (auto &s : branch.body) {
        if (s.kind != ast::EquationKind::Simple || !s.lhs || s.lhs->kind != ast::ExprKind::Ref || s.lhs->var < 0 ||
            !der[static_cast<std::size_t>(s.lhs->var)])
          continue;
        const SourceRange r = s.range;
        std::vector<ast::ExprPtr> args;
        args.push_back(std::move(s.lhs));
        args.push_back(std::move(s.rhs));
        s.lhs = ast::make_call("reinit", std::move(args), r);
        s.kind = ast::EquationKind::Call;
      }
  }
}

void Flattener::mark_free_inputs() {
  flat::Model &m = *model_;
  const std::size_t n = m.variables.size();
  std::vector<char> candidate(n, 0), others(n, 0), all(n, 0);
  bool any = false;
  for (std::size_t v = 0; v < n; ++v) {
    const flat::Variable &var = m.variables[v];
    if (!var.is_unknown() || var.type == flat::BaseType::String) continue;
    all[v] = 1;
    const bool input = var.causality == ast::Causality::Input && var.variability == ast::Variability::Continuous;
    (input ? candidate : others)[v] = 1;
    any = any || input;
  }
  if (!any) return;
  const auto rows = balance_rows(m);
  Matching matching(rows, n);
  for (std::size_t r = 0; r < rows.size(); ++r) matching.augment(r, others);
  for (std::size_t r = 0; r < rows.size(); ++r)
    if (!matching.row_matched(r)) matching.augment(r, all);
  for (std::size_t v = 0; v < n; ++v)
    if (candidate[v] && !matching.column_matched(v)) m.variables[v].top_level_input = true;
}

} // namespace mo::frontend::detail
