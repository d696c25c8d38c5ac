// Repeated equations: a simple equation written twice (`delta = car.delta;`
// twice in one section, as in JModelica's vehicle_turn example) says nothing
// the first did not. It is dropped with a warning at the repetition, so the
// model is not reported unbalanced for it (JModelica drops it as a trivial
// equation after alias elimination; we say so instead of doing it silently).
#include <fmt/format.h>

#include <string>
#include <unordered_map>

#include "flattener.hpp"
#include "mo/frontend/printer.hpp"

namespace mo::frontend::detail {

namespace {

std::string var_name(std::int32_t var) { return fmt::format("#{}", var); }

/// The text of `a = b`; `b = a` has the same key.
std::string equation_key(const ast::Equation &eq) {
  std::string lhs = print_expr(*eq.lhs, var_name), rhs = print_expr(*eq.rhs, var_name);
  if (rhs < lhs) std::swap(lhs, rhs);
  return lhs + " = " + rhs;
}

} // namespace

void Flattener::drop_repeated_equations() {
  std::unordered_map<std::string, SourceRange> seen;
  std::vector<ast::Equation> kept;
  kept.reserve(model_->equations.size());
  for (auto &eq : model_->equations) {
    if (eq.kind != ast::EquationKind::Simple || !eq.lhs || !eq.rhs) {
      kept.push_back(std::move(eq));
      continue;
    }
    auto [it, fresh] = seen.emplace(equation_key(eq), eq.range);
    if (fresh) {
      kept.push_back(std::move(eq));
      continue;
    }
    diags_.report(DiagId::RepeatedEquation, eq.range, "this equation repeats an earlier one; it is counted once");
    diags_.note(it->second, "the earlier equation");
  }
  model_->equations = std::move(kept);
}

} // namespace mo::frontend::detail
