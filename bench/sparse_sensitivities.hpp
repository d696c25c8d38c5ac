// WithSensitivities<Base> with the true sparsity of ∂f/∂x instead of the
// fixture's dense pattern, as generated code would declare it:
//   base rows i:        Base's ∂f_i/∂x_k pattern;
//   sensitivity row (i,j): every base state (f_x S + f_p depends on x through
//   f_x and f_p) and S(k, j) where Base's ∂f_i/∂x_k is structurally nonzero.
// Values are the fixture's, picked from its dense Jacobian.
#pragma once

#include "fixtures.hpp"

namespace mo::runtime::bench {

template <class Base>
class SparseSensitivities final : public Model {
public:
  SparseSensitivities() {
    const std::size_t nx = base_.info().num_base_states(), np = base_.info().parameters.size();
    const Base plain;
    const Sparsity& bfx = plain.jacobian_sparsity(Jacobian::f_x);
    std::vector<std::pair<int, int>> entries;
    for (int c = 0; c < bfx.cols; ++c)
      for (int k = bfx.col_start[c]; k < bfx.col_start[c + 1]; ++k) {
        int i = bfx.row_index[k];
        entries.emplace_back(i, c);
        for (std::size_t j = 0; j < np; ++j)
          entries.emplace_back(int(nx + std::size_t(i) * np + j), int(nx + std::size_t(c) * np + j));
      }
    for (std::size_t r = nx; r < nx * (1 + np); ++r)
      for (std::size_t c = 0; c < nx; ++c) entries.emplace_back(int(r), int(c));
    const int n = int(nx * (1 + np));
    f_x_ = Sparsity::from_triplets(n, n, entries);
  }
  const ModelInfo& info() const override { return base_.info(); }
  std::unique_ptr<Model> clone() const override { return std::make_unique<SparseSensitivities>(); }
  void initial_state(double t0, std::span<const double> u0, std::span<const double> p,
                     std::span<double> x0) override {
    base_.initial_state(t0, u0, p, x0);
  }
  void rhs(double t, std::span<const double> x, std::span<const double> u,
           std::span<const double> p, std::span<double> xdot) override {
    base_.rhs(t, x, u, p, xdot);
  }
  void outputs(double t, std::span<const double> x, std::span<const double> u,
               std::span<const double> p, std::span<double> y) override {
    base_.outputs(t, x, u, p, y);
  }
  const Sparsity& jacobian_sparsity(Jacobian block) const override {
    return block == Jacobian::f_x ? f_x_ : base_.jacobian_sparsity(block);
  }
  void jacobian_values(Jacobian block, double t, std::span<const double> x,
                       std::span<const double> u, std::span<const double> p,
                       std::span<double> values) override {
    if (block != Jacobian::f_x) return base_.jacobian_values(block, t, x, u, p, values);
    const Sparsity& dense = base_.jacobian_sparsity(Jacobian::f_x);
    dense_values_.resize(std::size_t(dense.nnz()));
    base_.jacobian_values(block, t, x, u, p, dense_values_);
    for (int c = 0; c < f_x_.cols; ++c)
      for (int k = f_x_.col_start[c]; k < f_x_.col_start[c + 1]; ++k)
        values[std::size_t(k)] = dense_values_[std::size_t(c * dense.rows + f_x_.row_index[k])];
  }

private:
  fixtures::WithSensitivities<Base> base_;
  Sparsity f_x_;
  std::vector<double> dense_values_;
};

}  // namespace mo::runtime::bench
