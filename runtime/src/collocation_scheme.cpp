#include "collocation_scheme.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace mo::runtime::detail {
namespace {

// Legendre polynomial P_n(x) by the three-term recurrence.
double legendre(int n, double x) {
  if (n == 0) return 1.0;
  double previous = 1.0, current = x;
  for (int k = 1; k < n; ++k) {
    double next = ((2.0 * k + 1.0) * x * current - k * previous) / (k + 1.0);
    previous = current;
    current = next;
  }
  return current;
}

// The collocation points' defining polynomial on x = 2τ − 1.
double node_polynomial(NodeFamily family, int points, double x) {
  return family == NodeFamily::gauss ? legendre(points, x)
                                     : legendre(points, x) - legendre(points - 1, x);
}

// Roots in (−1, 1) by sign changes on a fine grid, refined by bisection.
std::vector<double> interior_roots(NodeFamily family, int points) {
  std::vector<double> roots;
  const int samples = 4000;
  double a = -1.0, fa = node_polynomial(family, points, a);
  for (int s = 1; s < samples; ++s) {
    double b = -1.0 + 2.0 * s / samples, fb = node_polynomial(family, points, b);
    if (fb == 0.0) {  // a sample hit a root exactly (e.g. x = 0 for odd Gauss orders)
      roots.push_back(b);
    } else if (fa * fb < 0.0) {
      double lo = a, hi = b, flo = fa;
      for (int it = 0; it < 200 && hi - lo > 1e-16; ++it) {
        double mid = 0.5 * (lo + hi), fm = node_polynomial(family, points, mid);
        if (flo * fm <= 0.0) {
          hi = mid;
        } else {
          lo = mid, flo = fm;
        }
      }
      roots.push_back(0.5 * (lo + hi));
    }
    a = b, fa = fb;
  }
  return roots;
}

std::vector<double> barycentric_weights(const std::vector<double>& tau) {
  std::vector<double> w(tau.size(), 1.0);
  for (std::size_t k = 0; k < tau.size(); ++k)
    for (std::size_t m = 0; m < tau.size(); ++m)
      if (m != k) w[k] /= tau[k] - tau[m];
  return w;
}

// Weights w_j with Σ_j w_j τ_j^q = 1/(q+1), q = 0..K−1 (interpolatory quadrature).
std::vector<double> quadrature_weights(const std::vector<double>& points) {
  const auto k = static_cast<Eigen::Index>(points.size());
  Eigen::MatrixXd vandermonde(k, k);
  Eigen::VectorXd moments(k);
  for (Eigen::Index q = 0; q < k; ++q) {
    for (Eigen::Index j = 0; j < k; ++j) vandermonde(q, j) = std::pow(points[j], double(q));
    moments[q] = 1.0 / double(q + 1);
  }
  Eigen::VectorXd w = vandermonde.colPivHouseholderQr().solve(moments);
  return {w.data(), w.data() + k};
}

}  // namespace

std::vector<double> CollocationPolynomials::basis(double tau_value) const {
  std::vector<double> l(tau.size(), 1.0);
  for (std::size_t k = 0; k < tau.size(); ++k)
    for (std::size_t m = 0; m < tau.size(); ++m)
      if (m != k) l[k] *= (tau_value - tau[m]) / (tau[k] - tau[m]);
  return l;
}

CollocationPolynomials make_collocation_polynomials(NodeFamily family, int points) {
  if (points < 1 || points > 10)
    throw std::invalid_argument("collocation: n_cp must be in 1..10, got " +
                                std::to_string(points));
  std::vector<double> roots = interior_roots(family, points);
  if (family == NodeFamily::radau) roots.push_back(1.0);
  if (static_cast<int>(roots.size()) != points)
    throw std::logic_error("internal error: collocation root finding found " +
                           std::to_string(roots.size()) + " of " + std::to_string(points));
  CollocationPolynomials poly;
  poly.tau.push_back(0.0);
  for (double x : roots) poly.tau.push_back(x == 1.0 ? 1.0 : 0.5 * (x + 1.0));
  poly.weights = quadrature_weights({poly.tau.begin() + 1, poly.tau.end()});
  const auto n = static_cast<Eigen::Index>(poly.tau.size());
  std::vector<double> bw = barycentric_weights(poly.tau);
  poly.derivative = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index k = 0; k < n; ++k)
      if (k != j) poly.derivative(j, k) = (bw[k] / bw[j]) / (poly.tau[j] - poly.tau[k]);
    poly.derivative(j, j) = -poly.derivative.row(j).sum();
  }
  poly.at_end = poly.basis(1.0);
  return poly;
}

}  // namespace mo::runtime::detail
