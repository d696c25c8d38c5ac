// Sparse LU of large linear blocks in generated code (generated_support.cpp).
#pragma once

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <string>
#include <vector>

#include "mo/runtime/generated_support.hpp"

namespace mo::runtime::generated {

/// One block's sparse LU: the pattern of its entries (analysed once) and the
/// factors of the values last factorised.
struct SparseFactors {
  Eigen::SparseMatrix<double> matrix;  ///< the block's pattern, then its last values
  std::vector<int> position;           ///< entry k → index into matrix.valuePtr()
  std::vector<double> factored;        ///< entry values last factorised (empty: none)
  std::vector<double> values, rhs;     ///< this solve's entry values and -c, then z
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
  const BlockEntry* pattern = nullptr;  ///< the entries analysed (null: none yet)
  int pattern_size = 0;                 ///< and their number
};

/// Solves J z = f.rhs for J with the entry values f.values (one per entry,
/// all finite), f.rhs overwritten by z. Factorises only when the values
/// differ from the last ones factorised. Empty on success, else why it failed.
std::string solve_sparse(SparseFactors& f, const LinearBlock& block);

}  // namespace mo::runtime::generated
