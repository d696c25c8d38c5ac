// Balance check with Modelica's counting rules: as many scalar equations as
// unknowns (continuous and discrete variables that are not inputs of the
// model). An unbalanced model names the likely culprits.
#include "flattener.hpp"

#include <fmt/format.h>

namespace mo::frontend::detail {

void equation_uses(const ast::Equation &eq, std::vector<std::int32_t> &out) {
  std::vector<const ast::Expr *> work;
  std::vector<const ast::Equation *> eqs{&eq};
  while (!eqs.empty()) {
    const ast::Equation *e = eqs.back();
    eqs.pop_back();
    if (e->lhs) work.push_back(e->lhs.get());
    if (e->rhs) work.push_back(e->rhs.get());
    for (const auto &b : e->branches) {
      if (b.condition) work.push_back(b.condition.get());
      for (const auto &x : b.body) eqs.push_back(&x);
    }
  }
  while (!work.empty()) {
    const ast::Expr *x = work.back();
    work.pop_back();
    if (x->var >= 0) out.push_back(x->var);
    for (const auto &a : x->args)
      if (a) work.push_back(a.get());
  }
}

namespace {

/// Marks every variable referenced in `eq`.
void mark_uses(const ast::Equation &eq, std::vector<char> &used) {
  std::vector<std::int32_t> vars;
  equation_uses(eq, vars);
  for (const std::int32_t v : vars) used[v] = 1;
}

bool has_unknown(const ast::Equation &eq, const flat::Model &m) {
  std::vector<char> used(m.variables.size(), 0);
  mark_uses(eq, used);
  for (std::size_t i = 0; i < used.size(); ++i)
    if (used[i] && m.variables[i].is_unknown()) return true;
  return false;
}

} // namespace

void Flattener::check_balance() {
  std::size_t unknowns = 0, equations = 0;
  for (const auto &v : model_->variables)
    if (v.is_unknown() && v.type != flat::BaseType::String) ++unknowns;
  equations = balance_rows(*model_).size();
  if (unknowns == equations)
    return;
  const ast::ClassDef &def = *top_->cls->def;
  diags_.report(DiagId::UnbalancedModel, def.range,
                fmt::format("model '{}' is unbalanced: {} equation{} for {} unknown{} ({} {})", model_->name,
                            equations, equations == 1 ? "" : "s", unknowns, unknowns == 1 ? "" : "s",
                            equations > unknowns ? equations - unknowns : unknowns - equations,
                            equations > unknowns ? "too many equations" : "too few equations"));
  std::vector<char> used(model_->variables.size(), 0);
  for (const auto &eq : model_->equations)
    mark_uses(eq, used);
  unsigned shown = 0;
  for (std::size_t i = 0; i < used.size() && shown < 10; ++i) {
    const flat::Variable &v = model_->variables[i];
    if (!used[i] && v.is_unknown()) {
      diags_.note(v.range, "'" + v.name + "' appears in no equation");
      ++shown;
    }
  }
  shown = 0;
  for (const auto &eq : model_->equations) {
    if (shown >= 10) break;
    if (eq.kind == ast::EquationKind::Simple && !has_unknown(eq, *model_)) {
      diags_.note(eq.range, "this equation has no unknown");
      ++shown;
    }
  }
}

} // namespace mo::frontend::detail

namespace mo::frontend {

std::unique_ptr<flat::Model> flatten(Library &lib, const std::string &class_name, DiagnosticEngine &diags,
                                     const FlattenOptions &options) {
  detail::Flattener f(lib.impl(), diags, options);
  unsigned before = diags.error_count();
  auto model = f.run(class_name);
  if (diags.error_count() > before)
    return nullptr;
  return model;
}

} // namespace mo::frontend
