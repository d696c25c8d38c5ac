// Parameters computed by initial equations (`parameter Real a(fixed = false)`
// with `initial equation a = f(k);`), when the equation gives the parameter
// explicitly from parameters and constants: the equation becomes the
// parameter's binding, as if it had been written `parameter Real a = f(k);`.
// This is the form the MSL's filters use for their coefficients (through
// tuple equations of functions of the order and the cut-off frequency); a
// parameter defined implicitly, or from states at t0, stays an initial
// equation, and lowering makes the parameter an unknown of the initial system.
#include "flattener.hpp"

namespace mo::frontend::detail {

namespace {

/// The parameter declared `fixed = false`, without a binding, that `e` is a
/// plain reference to; -1 otherwise.
std::int32_t unbound_free_parameter(const ast::Expr &e, const flat::Model &m) {
  if (e.kind != ast::ExprKind::Ref || e.var < 0)
    return -1;
  const flat::Variable &v = m.variables[static_cast<std::size_t>(e.var)];
  if (!v.free_parameter() || v.binding || v.value)
    return -1;
  return e.var;
}

/// True if `e` references the parameter `var` itself (then it is implicit).
bool mentions(const ast::Expr &e, std::int32_t var) {
  std::vector<const ast::Expr *> todo{&e};
  while (!todo.empty()) {
    const ast::Expr *x = todo.back();
    todo.pop_back();
    if (x->kind == ast::ExprKind::Ref && x->var == var)
      return true;
    for (const auto &a : x->args)
      if (a)
        todo.push_back(a.get());
  }
  return false;
}

} // namespace

void Flattener::bind_computed_parameters(std::vector<ast::Equation> &produced) {
  std::vector<ast::Equation> kept;
  for (ast::Equation &eq : produced) {
    if (eq.kind == ast::EquationKind::Simple && eq.lhs && eq.rhs) {
      std::int32_t var = unbound_free_parameter(*eq.lhs, *model_);
      ast::ExprPtr *value = &eq.rhs;
      if (var < 0) {
        var = unbound_free_parameter(*eq.rhs, *model_);
        value = &eq.lhs;
      }
      if (var >= 0 && is_constant(**value) && !mentions(**value, var)) {
        flat::Variable &v = model_->variables[static_cast<std::size_t>(var)];
        v.binding = std::move(*value);
        v.attr.fixed = nullptr; // a parameter like any other from here on
        if (static_cast<std::size_t>(var) < param_state_.size())
          param_state_[static_cast<std::size_t>(var)] = 0;
        continue;
      }
    }
    kept.push_back(std::move(eq));
  }
  produced = std::move(kept);
}

} // namespace mo::frontend::detail
