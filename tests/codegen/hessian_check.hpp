// Hessians of a Model, ∇²_z(λᵀf) and ∇²_z(μᵀh) with z = (x, u, p), against
// central differences (Richardson extrapolated) of the gradient Jᵀλ built
// from the model's own Jacobian blocks; entries outside the pattern must be
// zero, and the pattern must be a valid lower triangle.
#pragma once

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "mo/runtime/model.hpp"

namespace mo::codegen::test {

/// ∇_z(wᵀf) (or wᵀh) at (x, u, p) from jacobian_values.
inline std::vector<double> weighted_gradient(runtime::Model& model, runtime::Hessian which, double t,
                                             const std::vector<double>& x, const std::vector<double>& u,
                                             const std::vector<double>& p,
                                             const std::vector<double>& weights) {
  using runtime::Jacobian;
  const bool f = which == runtime::Hessian::f;
  const Jacobian blocks[3] = {f ? Jacobian::f_x : Jacobian::h_x, f ? Jacobian::f_u : Jacobian::h_u,
                              f ? Jacobian::f_p : Jacobian::h_p};
  std::vector<double> g;
  for (Jacobian b : blocks) {
    const runtime::Sparsity& sp = model.jacobian_sparsity(b);
    std::vector<double> v(static_cast<std::size_t>(sp.nnz()));
    model.jacobian_values(b, t, x, u, p, v);
    for (int c = 0; c < sp.cols; ++c) {
      double s = 0;
      for (int k = sp.col_start[static_cast<std::size_t>(c)]; k < sp.col_start[static_cast<std::size_t>(c) + 1]; ++k)
        s += weights[static_cast<std::size_t>(sp.row_index[static_cast<std::size_t>(k)])] * v[static_cast<std::size_t>(k)];
      g.push_back(s);
    }
  }
  return g;
}

/// Checks model's Hessian `which` at one point for the given weights; returns
/// the number of entries that are nonzero numerically (> 1e-8).
inline int check_hessian(runtime::Model& model, runtime::Hessian which, double t, std::vector<double> x,
                         std::vector<double> u, std::vector<double> p, const std::vector<double>& weights,
                         double tol = 1e-6) {
  REQUIRE(model.provides_hessian(which));
  const runtime::Sparsity& sp = model.hessian_sparsity(which);
  const std::size_t nx = x.size(), nu = u.size(), np = p.size(), n = nx + nu + np;
  REQUIRE(sp.is_valid());
  REQUIRE(static_cast<std::size_t>(sp.rows) == n);
  REQUIRE(static_cast<std::size_t>(sp.cols) == n);
  for (int c = 0; c < sp.cols; ++c)
    for (int k = sp.col_start[static_cast<std::size_t>(c)]; k < sp.col_start[static_cast<std::size_t>(c) + 1]; ++k)
      REQUIRE(sp.row_index[static_cast<std::size_t>(k)] >= c);  // lower triangle
  std::vector<double> values(static_cast<std::size_t>(sp.nnz()), -12345.0);
  model.hessian_values(which, t, x, u, p, weights, values);
  auto arg = [&](std::size_t j) -> double& { return j < nx ? x[j] : j < nx + nu ? u[j - nx] : p[j - nx - nu]; };
  int nonzeros = 0;
  for (std::size_t c = 0; c < n; ++c) {
    const double at = arg(c);
    const double h = 1e-3 * std::max(1.0, std::fabs(at));
    auto central = [&](double step) {
      arg(c) = at + step;
      const auto plus = weighted_gradient(model, which, t, x, u, p, weights);
      arg(c) = at - step;
      const auto minus = weighted_gradient(model, which, t, x, u, p, weights);
      arg(c) = at;
      std::vector<double> d(n);
      for (std::size_t i = 0; i < n; ++i) d[i] = (plus[i] - minus[i]) / (2 * step);
      return d;
    };
    const auto d1 = central(h), d2 = central(h / 2);
    for (std::size_t r = c; r < n; ++r) {
      const double numeric = (4 * d2[r] - d1[r]) / 3;
      const int k = sp.find(static_cast<int>(r), static_cast<int>(c));
      const double exact = k < 0 ? 0.0 : values[static_cast<std::size_t>(k)];
      if (std::fabs(numeric) > 1e-8) ++nonzeros;
      INFO("Hessian " << (which == runtime::Hessian::f ? "f" : "h") << " entry (" << r << ", " << c << ")"
                      << (k < 0 ? " outside the pattern" : ""));
      CHECK(std::fabs(exact - numeric) <= tol * std::max({1.0, std::fabs(exact), std::fabs(numeric)}));
    }
  }
  return nonzeros;
}

}  // namespace mo::codegen::test
