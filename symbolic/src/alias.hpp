// Alias elimination on the DAE: equations of the forms
//   a = ±b          (also 0 = a ± b, the flow sums of two connectors)
//   a = c           (a constant, or an expression of parameters only)
//   v = der(x)      (v becomes the derivative variable of x)
// remove one variable each. Eliminated variables stay recoverable: each is
// recorded in Dae::eliminated with its value over the remaining symbols.
#pragma once

#include <cstddef>

#include "dae.hpp"

namespace mo::symbolic::detail {

/// Statistics of one alias elimination.
struct AliasStats {
  std::size_t eliminated = 0;  ///< variables removed
  std::size_t passes = 0;      ///< substitution passes until nothing changed
};

/// Eliminates aliases in `dae` in place (equations marked removed, variables
/// marked eliminated, remaining residuals and when-clauses rewritten).
AliasStats eliminate_aliases(Dae& dae);

}  // namespace mo::symbolic::detail
