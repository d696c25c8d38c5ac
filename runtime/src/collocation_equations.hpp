// The dynamics of one experiment as constraint rows (see collocation_nlp.hpp):
// initial condition b_0 − x0(p) = 0, then per element the K·nx collocation
// equations Σ_k D_jk X_ik − h_i f(X_ij) = 0 and nx continuity equations.
#pragma once

#include "collocation_nlp.hpp"

namespace mo::runtime::detail {

/// Initial, collocation and continuity equations of experiment `e`.
class CollocationEquations final : public ConstraintBlock {
public:
  CollocationEquations(const CollocationNlp& nlp, int experiment);
  [[nodiscard]] int rows() const override;
  void bounds(std::span<double> lo, std::span<double> hi) const override;
  void values(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) override;
  void jacobian(CollocationNlp& nlp, std::span<const double> v, int row0,
                SparseAssembler& jac) override;
  [[nodiscard]] bool has_hessian(const CollocationNlp& nlp) const override;
  void hessian(CollocationNlp& nlp, std::span<const double> v, std::span<const double> lambda,
               SparseAssembler& hess) override;
  void scaling(std::span<double> s) const override;

private:
  /// First row of element i's collocation equations (block-relative).
  [[nodiscard]] int element_row(int i) const { return nx_ + i * (k_ + 1) * nx_; }
  void add_sparse_block(CollocationNlp& nlp, Jacobian block, std::span<const double> v,
                        const PointRef& pt, int row, double scale, SparseAssembler& jac);

  int e_, nx_, k_, n_e_;
  std::vector<double> nominal_;
};

}  // namespace mo::runtime::detail
