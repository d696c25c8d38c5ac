// Dense LU factorisation with partial pivoting, for the small equation blocks
// of generated models:
//
//   P A = L U,   A z = b  ⇔  L U z = P b,
//
// A is n × n, row-major, factorised in place (L below the diagonal with unit
// diagonal implied, U on and above it). Blocks are small and dense after
// tearing-free lowering; sparse (KLU) blocks are not handled here.
#pragma once

#include <span>

namespace mo::runtime {

/// Factorises the row-major n × n matrix `a` (a.size() == n·n) in place,
/// recording the row swaps in `pivots` (size n). Returns false if a pivot is
/// zero or not finite (A singular or not finite); `a` is then unspecified.
bool lu_factor(std::span<double> a, std::span<int> pivots);

/// Solves A z = b with the factors of lu_factor(); b is overwritten by z.
void lu_solve(std::span<const double> lu, std::span<const int> pivots, std::span<double> b);

/// Solves A z = b in place (a overwritten by its factors, b by z).
/// Returns false if A is singular (see lu_factor); b is then unspecified.
bool solve_dense(std::span<double> a, std::span<int> pivots, std::span<double> b);

/// A z = b for a singular A (row-major n × n, b.size() == n): the solution of
/// least Euclidean norm, by a complete orthogonal decomposition whose rank
/// counts singular directions above 1e-12 of the largest. Returns true and
/// overwrites b with z if the equations are consistent, i.e. every residual
/// |(A z - b)_i| is within 1e-9 of its row's magnitude Σ_j |a_ij| max_j |z_j| + |b_i|
/// (the statically indeterminate torque of two stuck brakes on one shaft);
/// false, b unchanged, if they contradict each other or a value is not finite.
/// O(n³): for the blocks of generated models after LU has failed.
bool solve_minimum_norm(std::span<const double> a, std::span<double> b);

}  // namespace mo::runtime
