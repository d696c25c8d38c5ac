// The Jacobian-vector product of a lowered model and the structure of its
// Jacobians. One directional derivative with a seed symbol per state, input
// and parameter (σx, σu, σp) gives every block: seeding the columns of one
// colour with 1 (others 0) yields those columns' entries at once.
#pragma once

#include <vector>

#include "mo/codegen/program.hpp"
#include "mo/symbolic/directional.hpp"

namespace mo::codegen::detail {

/// Seeds, the differentiated steps and the derivative of every row.
struct Derivatives {
  std::vector<symbolic::Expr> seeds;  ///< σx (nx), then σu (nu), then σp (np)
  symbolic::Directional directional;  ///< steps computing the step targets' derivatives
  std::vector<symbolic::Expr> f_rows;  ///< d der(x_i); invalid handle if structurally zero
  std::vector<symbolic::Expr> h_rows;  ///< d y_j
  std::vector<symbolic::Expr> x0_rows; ///< d x0_i along σp
  symbolic::Directional initial_directional;  ///< model.initial_steps along σp (x0_rows use it)
};

/// Builds the derivatives in model.arena.
Derivatives build_derivatives(symbolic::OdeModel& model);

/// Second directional derivatives D²f[σ, τ]: the base steps followed by the
/// Jacobian-vector product steps, differentiated again along a second seed
/// vector τ (forward over forward; blocks become linear blocks with the
/// block's own Jacobian again).
struct SecondDerivatives {
  std::vector<symbolic::Expr> seeds;  ///< τx (nx), then τu (nu), then τp (np)
  symbolic::Directional directional;  ///< τ-derivatives of base and first-order targets
  std::vector<symbolic::Expr> f_rows;  ///< D² der(x_i)[σ, τ]; invalid handle if structurally zero
  std::vector<symbolic::Expr> h_rows;  ///< D² y_j[σ, τ]
};

/// Builds the second derivatives in model.arena from the first ones.
SecondDerivatives build_second_derivatives(symbolic::OdeModel& model, const Derivatives& first);

/// The seed columns each row depends on: `seeds[k]` is column k; dependencies
/// are propagated through `steps` (each list in order, lists in order).
std::vector<std::vector<int>> seed_columns(const symbolic::ExprArena& arena,
                                           const std::vector<symbolic::Expr>& seeds,
                                           const std::vector<const std::vector<symbolic::Step>*>& steps,
                                           const std::vector<symbolic::Expr>& rows);

/// The seed columns (0 .. nx+nu+np-1) each row depends on, ascending: the
/// structural pattern propagated through the differentiated steps.
std::vector<std::vector<int>> row_columns(const symbolic::ExprArena& arena, const Derivatives& d,
                                          const std::vector<symbolic::Expr>& rows);

/// Fills pattern and colouring of `code` from row dependencies restricted to
/// columns [first, first + count); entry_slot is filled by the caller.
void pattern_and_colouring(const std::vector<std::vector<int>>& rows, int first, int count,
                           JacobianCode& code);

}  // namespace mo::codegen::detail
