// Collocation polynomials on the unit element τ ∈ [0, 1].
//
//   Interpolation nodes τ_0 = 0 < τ_1 < ... < τ_K ≤ 1 (K = n_cp):
//   Radau IIA (LGR): τ_1..τ_K are the roots of P_K(2τ−1) − P_{K−1}(2τ−1), τ_K = 1;
//   Gauss (LG):      τ_1..τ_K are the roots of P_K(2τ−1), all interior.
//   x(τ) = Σ_k ℓ_k(τ) X_k with the Lagrange basis ℓ_k on τ_0..τ_K;
//   collocation: Σ_k D_jk X_k = h·f(X_j), D_jk = ℓ_k'(τ_j), j = 1..K;
//   quadrature: ∫_0^1 g dτ ≈ Σ_j w_j g(τ_j) (exact to degree 2K−2 resp. 2K−1).
#pragma once

#include <Eigen/Dense>

#include <vector>

namespace mo::runtime::detail {

/// Which family of collocation points (mirrors the public CollocationScheme).
enum class NodeFamily { radau, gauss };

/// The polynomial data of one scheme with K collocation points.
struct CollocationPolynomials {
  std::vector<double> tau;      ///< τ_0 = 0, then the K collocation points
  Eigen::MatrixXd derivative;   ///< (K+1) × (K+1): D_jk = ℓ_k'(τ_j)
  std::vector<double> weights;  ///< K quadrature weights of the collocation points
  std::vector<double> at_end;   ///< ℓ_k(1), k = 0..K (continuity coefficients)

  /// ℓ_k(τ), k = 0..K: interpolation weights of the element's nodes at τ.
  [[nodiscard]] std::vector<double> basis(double tau_value) const;
};

/// The polynomials for `points` collocation points of `family`.
/// Throws std::invalid_argument unless 1 ≤ points ≤ 10.
CollocationPolynomials make_collocation_polynomials(NodeFamily family, int points);

}  // namespace mo::runtime::detail
