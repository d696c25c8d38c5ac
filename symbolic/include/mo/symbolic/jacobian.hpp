// Sparse Jacobians J[i][j] = d outputs[i] / d wrt[j] of a vector function.
// The structure comes from dependency analysis (which leaves each output
// reaches); the values are reverse-mode gradients, one per output. Structure
// and values are separate entry points, as code generators need both.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "mo/symbolic/expr_arena.hpp"

namespace mo::symbolic {

/// A sparsity pattern in compressed sparse row form: the entries of row i
/// are col[row_start[i]] .. col[row_start[i+1]-1], columns ascending.
struct SparsityPattern {
  std::size_t rows = 0;                 ///< Number of outputs.
  std::size_t cols = 0;                 ///< Number of wrt leaves.
  std::vector<std::size_t> row_start;   ///< rows + 1 offsets into col.
  std::vector<std::uint32_t> col;       ///< Column of each entry.

  /// Number of structural nonzeros.
  std::size_t nonzeros() const { return col.size(); }
  /// True if (row, column) is an entry. Throws std::out_of_range for a row
  /// out of range.
  bool contains(std::size_t row, std::size_t column) const;
};

/// A Jacobian: its pattern and one derivative graph per entry.
struct SparseJacobian {
  SparsityPattern pattern;   ///< Where the entries are.
  std::vector<Expr> values;  ///< Parallel to pattern.col.
};

/// The entries (i, j) where outputs[i] reaches leaf wrt[j] in the graph. A
/// superset of the true nonzeros (e.g. floor(x) depends on x). Throws
/// std::invalid_argument if a wrt entry is not a leaf or appears twice.
SparsityPattern jacobian_sparsity(const ExprArena& arena, std::span<const Expr> outputs,
                                  std::span<const Expr> wrt);

/// The Jacobian with the entries of jacobian_sparsity() whose derivative does
/// not fold to the constant 0. Same failures as jacobian_sparsity().
SparseJacobian jacobian(ExprArena& arena, std::span<const Expr> outputs,
                        std::span<const Expr> wrt);

} // namespace mo::symbolic
