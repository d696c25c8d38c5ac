#include "design_fisher_nlp.hpp"

#include "mo/runtime/model.hpp"
#include "output_terms.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace mo::runtime::detail {
namespace {

// The symmetric "unit" of the F variable (a, b): ∂F/∂F_ab.
Eigen::MatrixXd unit(int n, int a, int b) {
  Eigen::MatrixXd e = Eigen::MatrixXd::Zero(n, n);
  e(a, b) = e(b, a) = 1.0;
  return e;
}

// (a, b) with a ≥ b of the packed index k = a(a+1)/2 + b.
std::pair<int, int> unpack(int k) {
  int a = 0;
  while ((a + 1) * (a + 2) / 2 <= k) ++a;
  return {a, k - a * (a + 1) / 2};
}

}  // namespace

// --- the lifted rows -------------------------------------------------------------

LiftedFisher::LiftedFisher(CollocationNlp& nlp, const MeasurementDesign& m,
                           std::vector<std::vector<std::size_t>> sensitivity_outputs,
                           bool positive_start)
    : samples_(nlp, m, std::move(sensitivity_outputs)), n_(samples_.size()) {
  std::vector<std::pair<int, int>> coupled;
  for (int a = 0; a < n_; ++a)
    for (int b = 0; b <= a; ++b) coupled.emplace_back(a, b);
  samples_.set_pattern(coupled);
  Eigen::MatrixXd f0 = trajectory_fisher(nlp, nlp.initial_guess());
  magnitude_ = std::max(1.0, f0.cwiseAbs().maxCoeff());
  if (positive_start) {  // A and D need a positive definite F to be evaluated at all
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(f0);
    const double floor = 1e-3 * magnitude_;
    if (eig.eigenvalues().minCoeff() < floor)
      f0 += (floor - eig.eigenvalues().minCoeff()) * Eigen::MatrixXd::Identity(n_, n_);
  }
  // Each entry scaled by sqrt(|F_aa F_bb|) at the start (the parameters' own
  // magnitudes differ by orders), at least 1e-6 of the largest entry and 1e-3
  // (an input that excites nothing gives F = 0: no magnitude to scale by).
  for (int a = 0; a < n_; ++a)
    for (int b = 0; b <= a; ++b)
      nominal_.push_back(std::max({std::sqrt(std::abs(f0(a, a) * f0(b, b))), 1e-6 * magnitude_, 1e-3}));
  f_ = nlp.num_variables();
  for (int k = 0; k < rows(); ++k) nlp.add_variables(1, {}, 0.0, 1.0 / nominal_[std::size_t(k)]);
  std::vector<double> guess = nlp.initial_guess();
  for (int a = 0; a < n_; ++a)
    for (int b = 0; b <= a; ++b) guess[std::size_t(f_var(a, b))] = f0(a, b);
  nlp.set_initial_guess(std::move(guess));
}

double LiftedFisher::nominal(int a, int b) const {
  if (a < b) std::swap(a, b);
  return nominal_[std::size_t(a * (a + 1) / 2 + b)];
}

int LiftedFisher::f_var(int a, int b) const {
  if (a < b) std::swap(a, b);
  return f_ + a * (a + 1) / 2 + b;
}

void LiftedFisher::bounds(std::span<double> lo, std::span<double> hi) const {
  std::fill(lo.begin(), lo.end(), 0.0);
  std::fill(hi.begin(), hi.end(), 0.0);
}

void LiftedFisher::scaling(std::span<double> s) const {
  for (std::size_t k = 0; k < s.size(); ++k) s[k] = 1.0 / nominal_[k];
}

bool LiftedFisher::has_hessian(const CollocationNlp& nlp) const {
  return nlp.model(0).provides_hessian(Hessian::h);
}

Eigen::MatrixXd LiftedFisher::fisher_variables(std::span<const double> v) const {
  Eigen::MatrixXd f(n_, n_);
  for (int a = 0; a < n_; ++a)
    for (int b = 0; b < n_; ++b) f(a, b) = v[std::size_t(f_var(a, b))];
  return f;
}

void LiftedFisher::values(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) {
  Eigen::MatrixXd f = trajectory_fisher(nlp, v);
  for (int a = 0; a < n_; ++a)
    for (int b = 0; b <= a; ++b)
      g[std::size_t(a * (a + 1) / 2 + b)] = v[std::size_t(f_var(a, b))] - f(a, b);
}

void LiftedFisher::jacobian(CollocationNlp& nlp, std::span<const double> v, int row0,
                            SparseAssembler& jac) {
  for (int k = 0; k < rows(); ++k) jac.add(row0 + k, f_ + k, 1.0);
  samples_.each_sample(nlp, v, [&](const PointRef& pt, const Eigen::MatrixXd& s,
                                   const FisherSamples::LocalJacobians& j) {
    VariableMap map = nlp.variable_map(pt);
    for (int a = 0; a < n_; ++a)
      for (int b = 0; b <= a; ++b) {  // ∂/∂z of −Σ_r w_r s_ra s_rb
        const int row = row0 + a * (a + 1) / 2 + b;
        const std::vector<int>& cols = samples_.columns(a, b);
        Eigen::VectorXd d = samples_.product_gradient(s, j, a, b);
        for (std::size_t c = 0; c < cols.size(); ++c)
          for (auto [var, coeff] : map[std::size_t(cols[c])]) jac.add(row, var, -coeff * d[Eigen::Index(c)]);
      }
  });
}

// ∇²Σ λ_ab g_ab = −∇² Σ_k Σ_r w_r s_rᵀ Λ s_r, Λ_aa = λ_aa, Λ_ab = Λ_ba = λ_ab/2.
void LiftedFisher::hessian(CollocationNlp& nlp, std::span<const double> v,
                           std::span<const double> lambda, SparseAssembler& hess) {
  Eigen::MatrixXd big_lambda(n_, n_);
  for (int a = 0; a < n_; ++a)
    for (int b = 0; b <= a; ++b) {
      const double l = lambda[std::size_t(a * (a + 1) / 2 + b)];
      big_lambda(a, b) = big_lambda(b, a) = a == b ? l : 0.5 * l;
    }
  samples_.add_hessian(nlp, v, big_lambda, -1.0, hess);
}

// --- A, T, D on the F variables ------------------------------------------------------

double FisherVariableCriterion::value(CollocationNlp&, std::span<const double> v) {
  return -criterion_information(criterion_, fisher_.fisher_variables(v));  // NaN: not PD
}

void FisherVariableCriterion::gradient(CollocationNlp&, std::span<const double> v,
                                       std::span<double> g) {
  const int n = fisher_.size();
  Eigen::MatrixXd f = fisher_.fisher_variables(v);
  Eigen::MatrixXd d;  // ∂φ/∂F for the objective φ (to minimise), F symmetric
  switch (criterion_) {
  case DesignCriterion::T: d = -Eigen::MatrixXd::Identity(n, n); break;
  case DesignCriterion::D: d = -f.inverse(); break;
  case DesignCriterion::A: d = -(f.inverse() * f.inverse()); break;
  case DesignCriterion::E:
    throw std::logic_error("internal error: the E criterion is an epigraph, not an objective");
  }
  for (int a = 0; a < n; ++a)
    for (int b = 0; b <= a; ++b) g[std::size_t(fisher_.f_var(a, b))] += a == b ? d(a, a) : 2.0 * d(a, b);
}

void FisherVariableCriterion::hessian(CollocationNlp&, std::span<const double> v, double factor,
                                      SparseAssembler& hess) {
  const int n = fisher_.size(), m = n * (n + 1) / 2;
  Eigen::MatrixXd fi = Eigen::MatrixXd::Identity(n, n);
  if (criterion_ != DesignCriterion::T) {
    Eigen::MatrixXd f = fisher_.fisher_variables(v);
    Eigen::LLT<Eigen::MatrixXd> llt(f);  // NaN values on failure: Ipopt backs off
    if (llt.info() == Eigen::Success) fi = llt.solve(Eigen::MatrixXd::Identity(n, n));
    else fi.setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  for (int k = 0; k < m; ++k)
    for (int l = 0; l <= k; ++l) {
      auto [a, b] = unpack(k);
      auto [c, d] = unpack(l);
      Eigen::MatrixXd e1 = unit(n, a, b), e2 = unit(n, c, d);
      double h = 0.0;
      switch (criterion_) {
      case DesignCriterion::T: break;
      case DesignCriterion::D: h = (fi * e1 * fi * e2).trace(); break;  // ∂²(−log det F)
      case DesignCriterion::A: h = 2.0 * (fi * fi * e1 * fi * e2).trace(); break;  // ∂² tr F⁻¹
      case DesignCriterion::E:
        throw std::logic_error("internal error: the E criterion is an epigraph, not an objective");
      }
      hess.add(fisher_.f_var(a, b), fisher_.f_var(c, d), factor * h);
    }
}

// --- E: F − tI = LLᵀ -------------------------------------------------------------------

FisherVariableEpigraph::FisherVariableEpigraph(CollocationNlp& nlp, const LiftedFisher& fisher)
    : fisher_(fisher), n_(fisher.size()) {
  Eigen::MatrixXd f0 = fisher_.fisher_variables(nlp.initial_guess());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(f0);
  const double lmin = eig.eigenvalues().minCoeff(), lmax = eig.eigenvalues().maxCoeff();
  const double t0 = lmin > 0.0 ? 0.5 * lmin : lmin - 1e-3 * (1.0 + std::abs(lmax));
  Eigen::LLT<Eigen::MatrixXd> llt(f0 - t0 * Eigen::MatrixXd::Identity(n_, n_));
  Eigen::MatrixXd l0 = llt.info() == Eigen::Success ? Eigen::MatrixXd(llt.matrixL())
                                                     : Eigen::MatrixXd::Identity(n_, n_);
  const double mag = fisher_.magnitude();
  t_ = nlp.add_variables(1, {}, t0, 1.0 / mag);
  l_ = nlp.num_variables();
  for (int a = 0; a < n_; ++a)
    for (int c = 0; c <= a; ++c) nlp.add_variables(1, {}, 0.0, 1.0 / std::sqrt(fisher_.nominal(a, a)));
  std::vector<double> guess = nlp.initial_guess();
  for (int a = 0; a < n_; ++a)
    for (int c = 0; c <= a; ++c) guess[std::size_t(l_var(a, c))] = l0(a, c);
  nlp.set_initial_guess(std::move(guess));
}

void FisherVariableEpigraph::bounds(std::span<double> lo, std::span<double> hi) const {
  std::fill(lo.begin(), lo.end(), 0.0);
  std::fill(hi.begin(), hi.end(), 0.0);
}

void FisherVariableEpigraph::scaling(std::span<double> s) const {
  for (int a = 0; a < n_; ++a)
    for (int b = 0; b <= a; ++b) s[std::size_t(a * (a + 1) / 2 + b)] = 1.0 / fisher_.nominal(a, b);
}

void FisherVariableEpigraph::values(CollocationNlp&, std::span<const double> v,
                                    std::span<double> g) {
  for (int a = 0; a < n_; ++a)
    for (int b = 0; b <= a; ++b) {
      double llt = 0.0;
      for (int c = 0; c <= b; ++c) llt += v[std::size_t(l_var(a, c))] * v[std::size_t(l_var(b, c))];
      g[std::size_t(a * (a + 1) / 2 + b)] =
          v[std::size_t(fisher_.f_var(a, b))] - (a == b ? v[std::size_t(t_)] : 0.0) - llt;
    }
}

void FisherVariableEpigraph::jacobian(CollocationNlp&, std::span<const double> v, int row0,
                                      SparseAssembler& jac) {
  for (int a = 0; a < n_; ++a)
    for (int b = 0; b <= a; ++b) {
      const int row = row0 + a * (a + 1) / 2 + b;
      jac.add(row, fisher_.f_var(a, b), 1.0);
      if (a == b) jac.add(row, t_, -1.0);
      for (int c = 0; c <= b; ++c) {
        jac.add(row, l_var(a, c), -v[std::size_t(l_var(b, c))]);
        jac.add(row, l_var(b, c), -v[std::size_t(l_var(a, c))]);
      }
    }
}

void FisherVariableEpigraph::hessian(CollocationNlp&, std::span<const double>,
                                     std::span<const double> lambda, SparseAssembler& hess) {
  // (LLᵀ)_ab = Σ_{c ≤ b} L_ac L_bc: ∂² is 1 at (L_ac, L_bc), 2 on the diagonal for a = b.
  for (int a = 0; a < n_; ++a)
    for (int b = 0; b <= a; ++b) {
      const double l = lambda[std::size_t(a * (a + 1) / 2 + b)];
      for (int c = 0; c <= b; ++c) {
        if (a == b) hess.add(l_var(a, c), l_var(a, c), -2.0 * l);
        else hess.add(std::max(l_var(a, c), l_var(b, c)), std::min(l_var(a, c), l_var(b, c)), -l);
      }
    }
}

}  // namespace mo::runtime::detail
