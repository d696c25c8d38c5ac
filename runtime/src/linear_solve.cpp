// Doolittle LU with partial pivoting, and the minimum-norm solution of a
// singular system; see linear_solve.hpp.
#include "mo/runtime/linear_solve.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

namespace mo::runtime {

namespace {
std::size_t order_of(std::span<const int> pivots) { return pivots.size(); }
}  // namespace

bool lu_factor(std::span<double> a, std::span<int> pivots) {
  const std::size_t n = order_of(pivots);
  for (std::size_t k = 0; k < n; ++k) {
    std::size_t best = k;
    double best_abs = std::fabs(a[k * n + k]);
    for (std::size_t r = k + 1; r < n; ++r) {
      const double v = std::fabs(a[r * n + k]);
      if (v > best_abs) best = r, best_abs = v;
    }
    if (!(best_abs > 0.0) || !std::isfinite(best_abs)) return false;
    pivots[k] = static_cast<int>(best);
    if (best != k)
      for (std::size_t c = 0; c < n; ++c) std::swap(a[k * n + c], a[best * n + c]);
    const double pivot = a[k * n + k];
    for (std::size_t r = k + 1; r < n; ++r) {
      const double factor = a[r * n + k] / pivot;
      a[r * n + k] = factor;
      if (factor == 0.0) continue;
      for (std::size_t c = k + 1; c < n; ++c) a[r * n + c] -= factor * a[k * n + c];
    }
  }
  return true;
}

void lu_solve(std::span<const double> lu, std::span<const int> pivots, std::span<double> b) {
  const std::size_t n = order_of(pivots);
  for (std::size_t k = 0; k < n; ++k) {
    const auto p = static_cast<std::size_t>(pivots[k]);
    if (p != k) std::swap(b[k], b[p]);
  }
  for (std::size_t r = 0; r < n; ++r)  // L y = P b, unit diagonal
    for (std::size_t c = 0; c < r; ++c) b[r] -= lu[r * n + c] * b[c];
  for (std::size_t r = n; r-- > 0;) {  // U z = y
    for (std::size_t c = r + 1; c < n; ++c) b[r] -= lu[r * n + c] * b[c];
    b[r] /= lu[r * n + r];
  }
}

bool solve_dense(std::span<double> a, std::span<int> pivots, std::span<double> b) {
  if (!lu_factor(a, pivots)) return false;
  lu_solve(a, pivots, b);
  return true;
}

bool solve_minimum_norm(std::span<const double> a, std::span<double> b) {
  const auto n = static_cast<Eigen::Index>(b.size());
  if (!std::all_of(a.begin(), a.end(), [](double v) { return std::isfinite(v); }) ||
      !std::all_of(b.begin(), b.end(), [](double v) { return std::isfinite(v); }))
    return false;
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> m(a.data(), n, n);
  const Eigen::Map<const Eigen::VectorXd> rhs(b.data(), n);
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(n, n);
  cod.setThreshold(1e-12);
  cod.compute(m);
  const Eigen::VectorXd z = cod.solve(rhs);
  if (!z.allFinite()) return false;
  // Rounding leaves each residual near eps·Σ_j |a_ij| max|z| (the whole
  // system's error spreads into every row's unknowns), however small that
  // row's own terms.
  const Eigen::VectorXd residual = m * z - rhs;
  const Eigen::VectorXd magnitude = m.cwiseAbs().rowwise().sum() * z.lpNorm<Eigen::Infinity>() + rhs.cwiseAbs();
  for (Eigen::Index i = 0; i < n; ++i)
    if (!(std::fabs(residual[i]) <= 1e-9 * magnitude[i])) return false;
  std::copy(z.begin(), z.end(), b.begin());
  return true;
}

}  // namespace mo::runtime
