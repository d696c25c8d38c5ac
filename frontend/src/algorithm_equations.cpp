// Algorithm sections of models and blocks as equations. A section whose
// statements are assignments `v := e` (and `when` statements of such,
// assert/terminate/reinit calls) where each variable is assigned by one
// statement and not read by an earlier one means the same as the equations
// `v = e`: every value it reads is either assigned before (then equal to its
// equation's right side) or not assigned at all. Other sections stay
// algorithms, which the flattener reports as unsupported.
#include "ast_builder.hpp"

#include <set>
#include <string>

namespace mo::frontend::detail {

using namespace ast;

namespace {

/// Adds the first name of every reference read in `e` to `out`; arguments of
/// pre() read the previous value, which assignments do not change.
void reads(const Expr &root, std::set<std::string> &out) {
  std::vector<const Expr *> work{&root};
  while (!work.empty()) {
    const Expr *e = work.back();
    work.pop_back();
    if (e->kind == ExprKind::Ref && !e->ref.parts.empty())
      out.insert(e->ref.parts[0].name);
    if (e->kind == ExprKind::Call && e->ref.is_simple() && e->ref.parts[0].name == "pre")
      continue;
    for (const auto &p : e->ref.parts)
      for (const auto &s : p.subscripts)
        if (s) work.push_back(s.get());
    for (const auto &a : e->args)
      if (a) work.push_back(a.get());
    for (const auto &n : e->named)
      if (n.value) work.push_back(n.value.get());
    for (const auto &row : e->rows)
      for (const auto &x : row)
        if (x) work.push_back(x.get());
  }
}

bool is_call_statement(const Statement &st) {
  if (st.kind != StatementKind::Call || !st.value || st.value->kind != ExprKind::Call || !st.value->ref.is_simple())
    return false;
  const std::string &n = st.value->ref.parts[0].name;
  return n == "assert" || n == "terminate" || n == "reinit";
}

/// Checks one list of statements (a section or a when-branch); `assigned`
/// collects the names assigned in it, `read` the names read so far.
bool check(const std::vector<Statement> &body, std::set<std::string> &assigned, std::set<std::string> &read,
           bool in_when) {
  for (const Statement &st : body) {
    switch (st.kind) {
    case StatementKind::Assign: {
      if (st.targets.size() != 1 || !st.targets[0] || st.targets[0]->kind != ExprKind::Ref)
        return false;
      const std::string &name = st.targets[0]->ref.parts[0].name;
      reads(*st.value, read);
      for (const auto &p : st.targets[0]->ref.parts)
        for (const auto &s : p.subscripts)
          if (s) reads(*s, read);
      if (read.count(name) || !assigned.insert(name).second)
        return false;
      break;
    }
    case StatementKind::Call:
      if (!is_call_statement(st))
        return false;
      reads(*st.value, read);
      break;
    case StatementKind::When: {
      if (in_when)
        return false;
      std::set<std::string> first;
      for (std::size_t b = 0; b < st.branches.size(); ++b) {
        std::set<std::string> mine, branch_read = read;
        if (!st.branches[b].condition)
          return false;
        reads(*st.branches[b].condition, branch_read);
        if (!check(st.branches[b].body, mine, branch_read, true))
          return false;
        if (b == 0)
          first = mine;
        else if (mine != first) // every branch assigns the same variables
          return false;
      }
      for (const auto &n : first)
        if (read.count(n) || !assigned.insert(n).second)
          return false;
      break;
    }
    case StatementKind::Break:
    case StatementKind::Return:
    case StatementKind::If:
    case StatementKind::For:
    case StatementKind::While:
      return false;
    }
  }
  return true;
}

void convert(std::vector<Statement> &body, std::vector<Equation> &out) {
  for (Statement &st : body) {
    Equation eq;
    eq.range = st.range;
    switch (st.kind) {
    case StatementKind::Assign:
      eq.kind = EquationKind::Simple;
      eq.lhs = std::move(st.targets[0]);
      eq.rhs = std::move(st.value);
      break;
    case StatementKind::Call:
      eq.kind = EquationKind::Call;
      eq.lhs = std::move(st.value);
      break;
    case StatementKind::When:
      eq.kind = EquationKind::When;
      for (StatementBranch &b : st.branches) {
        EquationBranch eb;
        eb.condition = std::move(b.condition);
        eb.range = b.range;
        convert(b.body, eb.body);
        eq.branches.push_back(std::move(eb));
      }
      break;
    case StatementKind::Break:
    case StatementKind::Return:
    case StatementKind::If:
    case StatementKind::For:
    case StatementKind::While:
      continue; // excluded by check()
    }
    out.push_back(std::move(eq));
  }
}

} // namespace

bool algorithm_as_equations(std::vector<Statement> &section, std::vector<Equation> &out) {
  std::set<std::string> assigned, read;
  if (!check(section, assigned, read, false))
    return false;
  convert(section, out);
  return true;
}

} // namespace mo::frontend::detail
