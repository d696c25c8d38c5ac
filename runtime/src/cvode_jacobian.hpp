// The matrix and linear solver of CVODES' Newton iteration, and how the
// model's ∂f/∂x (its own CSC pattern) is written into that matrix: dense LU
// for small or dense Jacobians, KLU (sparse LU) on the pattern of ∂f/∂x plus
// the diagonal for large sparse ones. A model whose phases or components are
// stacked (a multi-phase study's model: thousands of states, a few per row)
// would spend its simulations in dense n³ factorisations.
#pragma once

#include "mo/runtime/model.hpp"
#include "mo/runtime/simulate.hpp"

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>
#include <sundials/sundials_types.h>

#include <span>
#include <vector>

namespace mo::runtime::detail {

class CvodeJacobian {
public:
  /// Automatic: KLU for at least kSparseStates states whose pattern (with the
  /// diagonal) fills at most a tenth of the matrix. Sparse needs the model's
  /// Jacobian (`model_jacobian`): CVODES' difference quotients are dense only.
  /// `n` is CVODES' size: fx's, or 1 for a model without states (a dummy state).
  CvodeJacobian(const Sparsity& fx, sunindextype n, LinearSolverChoice choice, bool model_jacobian);

  static constexpr int kSparseStates = 100;

  [[nodiscard]] bool sparse() const { return sparse_; }
  /// A new matrix and a linear solver for it (the caller destroys both);
  /// nullptr where SUNDIALS could not create them.
  [[nodiscard]] SUNMatrix make_matrix(SUNContext ctx) const;
  [[nodiscard]] SUNLinearSolver make_solver(N_Vector y, SUNMatrix a, SUNContext ctx) const;
  /// jac = ∂f/∂x from the model's values, in fx's CSC order.
  void store(SUNMatrix jac, std::span<const double> values) const;
  /// Column c of ∂f/∂x, all rows (a difference quotient); the sparse matrix
  /// keeps the rows of its pattern. Call begin_columns() first.
  void begin_columns(SUNMatrix jac) const;
  void store_column(SUNMatrix jac, int c, std::span<const double> column) const;

private:
  void set_pattern(SUNMatrix jac) const;

  Sparsity fx_;
  sunindextype n_ = 0;
  bool sparse_ = false;
  std::vector<sunindextype> col_start_, rows_;  // the sparse pattern: fx_ and the diagonal
  std::vector<sunindextype> slot_;              // per entry of fx_: its place in rows_
};

}  // namespace mo::runtime::detail
