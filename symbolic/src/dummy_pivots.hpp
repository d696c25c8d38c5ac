// Numeric checks of dummy-derivative selection. The tiered matching of
// select_states chooses dummies from the structure; a structurally valid
// choice can still be numerically singular (the star point and zero-sequence
// equations of a three-phase machine both say Σ i_k = ..., so no two phase
// currents and the zero-sequence current make a regular choice with them).
// These functions test a choice on the level's Jacobian at a point and make a
// regular one by Gaussian elimination with column choice by cost.
#pragma once

#include <optional>
#include <vector>

namespace mo::symbolic::detail {

/// A level's Jacobian at a point: rows × columns, dense.
using DenseJacobian = std::vector<std::vector<double>>;

/// True if the block of `jac` made of each row r with chosen[r] ≥ 0 and
/// column chosen[r] is nonsingular (relative pivot tolerance 1e-9).
bool regular_choice(const DenseJacobian& jac, const std::vector<int>& chosen);

/// One column per row such that the block is nonsingular: rows are reduced in
/// order by the pivots before them, and each takes, among the columns where
/// its reduced row is not negligible, the one of least `cost` (then the
/// largest magnitude). nullopt if a row is numerically a combination of the
/// rows before it.
std::optional<std::vector<int>> regular_columns(const DenseJacobian& jac,
                                                const std::vector<int>& cost);

}  // namespace mo::symbolic::detail
