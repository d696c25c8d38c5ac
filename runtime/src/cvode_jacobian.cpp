// CVODES' matrix and linear solver; see cvode_jacobian.hpp.
#include "cvode_jacobian.hpp"

#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <set>

namespace mo::runtime::detail {

CvodeJacobian::CvodeJacobian(const Sparsity& fx, sunindextype n_cvodes, LinearSolverChoice choice,
                             bool model_jacobian)
    : fx_(fx), n_(n_cvodes) {
  const int n = fx_.cols;
  for (int c = 0; c < n; ++c) {
    col_start_.push_back(sunindextype(rows_.size()));
    std::set<int> rows(fx_.row_index.begin() + fx_.col_start[c], fx_.row_index.begin() + fx_.col_start[c + 1]);
    rows.insert(c);
    rows_.insert(rows_.end(), rows.begin(), rows.end());
  }
  col_start_.push_back(sunindextype(rows_.size()));
  for (int c = 0; c < n; ++c)
    for (int k = fx_.col_start[c]; k < fx_.col_start[c + 1]; ++k) {
      const auto first = rows_.begin() + col_start_[std::size_t(c)], last = rows_.begin() + col_start_[std::size_t(c) + 1];
      slot_.push_back(sunindextype(std::lower_bound(first, last, sunindextype(fx_.row_index[std::size_t(k)])) - rows_.begin()));
    }
  const bool sparse_pays = n >= kSparseStates && double(rows_.size()) <= 0.1 * double(n) * double(n);
  sparse_ = model_jacobian && n > 0 && n_ == n &&
            (choice == LinearSolverChoice::sparse || (choice == LinearSolverChoice::automatic && sparse_pays));
}

SUNMatrix CvodeJacobian::make_matrix(SUNContext ctx) const {
  if (!sparse_) return SUNDenseMatrix(n_, n_, ctx);
  SUNMatrix a = SUNSparseMatrix(n_, n_, sunindextype(rows_.size()), CSC_MAT, ctx);
  if (a) set_pattern(a);
  return a;
}

SUNLinearSolver CvodeJacobian::make_solver(N_Vector y, SUNMatrix a, SUNContext ctx) const {
  return sparse_ ? SUNLinSol_KLU(y, a, ctx) : SUNLinSol_Dense(y, a, ctx);
}

void CvodeJacobian::set_pattern(SUNMatrix jac) const {
  std::copy(col_start_.begin(), col_start_.end(), SUNSparseMatrix_IndexPointers(jac));
  std::copy(rows_.begin(), rows_.end(), SUNSparseMatrix_IndexValues(jac));
  std::fill_n(SUNSparseMatrix_Data(jac), rows_.size(), 0.0);
}

void CvodeJacobian::store(SUNMatrix jac, std::span<const double> values) const {
  if (sparse_) {
    set_pattern(jac);
    double* data = SUNSparseMatrix_Data(jac);
    for (std::size_t k = 0; k < slot_.size(); ++k) data[slot_[k]] = values[k];
    return;
  }
  SUNMatZero(jac);
  for (int c = 0; c < fx_.cols; ++c) {
    double* column = SUNDenseMatrix_Column(jac, c);
    for (int k = fx_.col_start[c]; k < fx_.col_start[c + 1]; ++k) column[fx_.row_index[k]] = values[std::size_t(k)];
  }
}

void CvodeJacobian::begin_columns(SUNMatrix jac) const {
  if (sparse_) set_pattern(jac);
  else SUNMatZero(jac);
}

void CvodeJacobian::store_column(SUNMatrix jac, int c, std::span<const double> column) const {
  if (!sparse_) {
    std::copy(column.begin(), column.end(), SUNDenseMatrix_Column(jac, c));
    return;
  }
  double* data = SUNSparseMatrix_Data(jac);
  for (sunindextype k = col_start_[std::size_t(c)]; k < col_start_[std::size_t(c) + 1]; ++k)
    data[k] = column[std::size_t(rows_[std::size_t(k)])];
}

}  // namespace mo::runtime::detail
