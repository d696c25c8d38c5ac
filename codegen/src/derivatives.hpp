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
};

/// Builds the derivatives in model.arena.
Derivatives build_derivatives(symbolic::OdeModel& model);

/// The seed columns (0 .. nx+nu+np-1) each row depends on, ascending: the
/// structural pattern propagated through the differentiated steps.
std::vector<std::vector<int>> row_columns(const symbolic::ExprArena& arena, const Derivatives& d,
                                          const std::vector<symbolic::Expr>& rows);

/// Fills pattern and colouring of `code` from row dependencies restricted to
/// columns [first, first + count); entry_slot is filled by the caller.
void pattern_and_colouring(const std::vector<std::vector<int>>& rows, int first, int count,
                           JacobianCode& code);

}  // namespace mo::codegen::detail
