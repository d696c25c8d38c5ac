// Where a model switches, for the diagnostics of studies on models with events; see study_events.hpp.
#include "study_events.hpp"

#include <vector>

namespace mo::tools {

namespace {

namespace ast = frontend::ast;

bool is_relation(const ast::Expr& e) {
  return e.kind == ast::ExprKind::Binary &&
         (e.op == ast::Op::Lt || e.op == ast::Op::Le || e.op == ast::Op::Gt || e.op == ast::Op::Ge);
}

/// The first relation under `root` (iterative: expressions may be deep).
const ast::Expr* first_relation(const ast::Expr* root) {
  std::vector<const ast::Expr*> stack{root};
  while (!stack.empty()) {
    const ast::Expr* e = stack.back();
    stack.pop_back();
    if (!e) continue;
    if (is_relation(*e)) return e;
    for (auto it = e->args.rbegin(); it != e->args.rend(); ++it) stack.push_back(it->get());
  }
  return nullptr;
}

/// The first when-equation, or else the first relation, in the equations.
std::pair<const ast::Equation*, const ast::Expr*> first_switch(const frontend::flat::Model& flat) {
  std::vector<const ast::Equation*> stack;
  for (auto it = flat.equations.rbegin(); it != flat.equations.rend(); ++it) stack.push_back(&*it);
  const ast::Expr* relation = nullptr;
  while (!stack.empty()) {
    const ast::Equation* eq = stack.back();
    stack.pop_back();
    if (eq->kind == ast::EquationKind::When) return {eq, nullptr};
    if (!relation) relation = first_relation(eq->lhs.get());
    if (!relation) relation = first_relation(eq->rhs.get());
    for (const auto& b : eq->branches) {
      if (!relation) relation = first_relation(b.condition.get());
      for (auto it = b.body.rbegin(); it != b.body.rend(); ++it) stack.push_back(&*it);
    }
    for (auto it = eq->body.rbegin(); it != eq->body.rend(); ++it) stack.push_back(&*it);
  }
  return {nullptr, relation};
}

/// The when/elsewhen branches of the equations, in order.
std::vector<const ast::EquationBranch*> when_branches(const frontend::flat::Model& flat) {
  std::vector<const ast::EquationBranch*> out;
  std::vector<const ast::Equation*> stack;
  for (auto it = flat.equations.rbegin(); it != flat.equations.rend(); ++it) stack.push_back(&*it);
  while (!stack.empty()) {
    const ast::Equation* eq = stack.back();
    stack.pop_back();
    if (eq->kind == ast::EquationKind::When) {
      for (const auto& b : eq->branches) out.push_back(&b);
      continue;
    }
    for (auto b = eq->branches.rbegin(); b != eq->branches.rend(); ++b)
      for (auto it = b->body.rbegin(); it != b->body.rend(); ++it) stack.push_back(&*it);
    for (auto it = eq->body.rbegin(); it != eq->body.rend(); ++it) stack.push_back(&*it);
  }
  return out;
}

}  // namespace

frontend::SourceRange event_source(const frontend::flat::Model& flat, std::optional<std::size_t> when) {
  if (when) {
    const auto branches = when_branches(flat);
    if (*when < branches.size()) return branches[*when]->range;
  }
  const auto [eq, relation] = first_switch(flat);
  return eq ? eq->range : relation ? relation->range : flat.optimization->range;
}

}  // namespace mo::tools
