// Which variables the model itself differentiates (state selection prefers
// them as states); see dae_build.hpp.
#include <algorithm>

#include "dae_build.hpp"
#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic::detail {

void mark_source_derivatives(Dae& dae) {
  for (DaeVar& v : dae.vars) v.source_derivative = !v.eliminated && v.derivative != none;
  for (const DaeEq& eq : dae.eqs) {
    if (eq.removed) continue;
    for (Expr leaf : leaves(dae.arena, std::span(&eq.residual, 1))) {
      const int d = dae.arena.kind(leaf) == ExprKind::Symbol ? dae.var_of(leaf) : none;
      if (d == none || dae.vars[static_cast<std::size_t>(d)].integral == none) continue;
      DaeVar& base = dae.vars[static_cast<std::size_t>(dae.vars[static_cast<std::size_t>(d)].integral)];
      if (base.linear_derivative) continue;
      const Expr c = derivative(dae.arena, eq.residual, leaf);
      const auto coefficient_leaves = leaves(dae.arena, std::span(&c, 1));
      base.linear_derivative = std::all_of(coefficient_leaves.begin(), coefficient_leaves.end(), [&](Expr l) {
        return dae.arena.kind(l) == ExprKind::Symbol && dae.arena.symbol_info(l).role == SymbolRole::Parameter;
      });
    }
  }
}

}  // namespace mo::symbolic::detail
