#include "fisher_terms.hpp"

#include "output_terms.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace mo::runtime::detail {
namespace {

Eigen::MatrixXd dense_jacobian(Model& model, Jacobian block, double t, std::span<const double> x,
                               std::span<const double> u, std::span<const double> p) {
  const Sparsity& sp = model.jacobian_sparsity(block);
  std::vector<double> values(std::size_t(sp.nnz()));
  model.jacobian_values(block, t, x, u, p, values);
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(sp.rows, sp.cols);
  for (int c = 0; c < sp.cols; ++c)
    for (int k = sp.col_start[c]; k < sp.col_start[c + 1]; ++k) m(sp.row_index[k], c) = values[k];
  return m;
}

// ∇_z(μᵀh) = [h_x h_u h_p]ᵀ μ at (t, x, u, p).
Eigen::VectorXd output_gradient(Model& model, double t, std::span<const double> x,
                                std::span<const double> u, std::span<const double> p,
                                const Eigen::VectorXd& mu) {
  Eigen::VectorXd g(Eigen::Index(x.size() + u.size() + p.size()));
  g << dense_jacobian(model, Jacobian::h_x, t, x, u, p).transpose() * mu,
      dense_jacobian(model, Jacobian::h_u, t, x, u, p).transpose() * mu,
      dense_jacobian(model, Jacobian::h_p, t, x, u, p).transpose() * mu;
  return g;
}

Eigen::MatrixXd symmetric_unit(int n, int a, int b) {
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(n, n);
  g(a, b) = g(b, a) = a == b ? 1.0 : 0.5;
  return g;
}

}  // namespace

std::vector<std::vector<int>> sensitivity_state_map(const ModelInfo& info, const std::vector<std::size_t>& parameters) {
  const std::size_t base = info.num_base_states();
  std::vector<std::vector<int>> map(base, std::vector<int>(parameters.size(), -1));
  for (std::size_t s = 0; s < info.states.size(); ++s)
    if (const auto& of = info.states[s].sensitivity)
      for (std::size_t j = 0; j < parameters.size(); ++j)
        if (of->parameter == parameters[j] && of->state < base) map[of->state][j] = int(s);
  return map;
}

bool has_sensitivity_states(const ModelInfo& info, const std::vector<std::size_t>& parameters) {
  const auto map = sensitivity_state_map(info, parameters);
  for (std::size_t j = 0; j < parameters.size(); ++j)
    if (std::none_of(map.begin(), map.end(), [&](const auto& row) { return row[j] >= 0; })) return false;
  return true;
}

FisherEvaluator::FisherEvaluator(const CollocationNlp& nlp, MeasurementDesign measurements,
                                 std::vector<std::size_t> parameters)
    : m_(std::move(measurements)), parameters_(std::move(parameters)) {
  const ModelInfo& info = nlp.info();
  base_states_ = info.num_base_states();
  if (parameters_.empty()) throw ProblemError("input design needs at least one parameter");
  if (m_.outputs.empty() || m_.sigma.size() != m_.outputs.size())
    throw ProblemError("input design needs measured outputs with one sigma each");
  for (std::size_t k = 0; k < m_.outputs.size(); ++k)
    if (m_.outputs[k] >= info.outputs.size() || !(m_.sigma[k] > 0.0))
      throw ProblemError("measured output index out of range or sigma not positive");
  // Missing S(i, j) are structurally zero (the compiler emits only nonzero
  // ones); a parameter without any sensitivity state is an error.
  for (std::size_t s = 0; s < base_states_; ++s)
    if (info.states[s].sensitivity)
      throw ProblemError("sensitivity state " + info.states[s].name +
                         " among the base states (base states must come first)");
  sensitivity_state_ = sensitivity_state_map(info, parameters_);
  for (std::size_t j = 0; j < parameters_.size(); ++j)
    if (std::none_of(sensitivity_state_.begin(), sensitivity_state_.end(), [&](const auto& row) { return row[j] >= 0; }))
      throw ProblemError("the model has no sensitivity states for parameter " +
                         info.parameters.at(parameters_[j]).name);
  const ExperimentSetup& ex = nlp.experiment(0);
  std::set<int> vars;
  for (double t : m_.times) {
    if (t < ex.t0 || t > ex.tf) throw ProblemError("measurement time outside [t0, tf]");
    points_.push_back(nlp.point_at(0, t));
    for (const auto& entries : nlp.variable_map(points_.back()))
      for (auto [var, coeff] : entries) vars.insert(var);
  }
  variables_.assign(vars.begin(), vars.end());
}

FisherEvaluator::Sample FisherEvaluator::evaluate(CollocationNlp& nlp, std::span<const double> v,
                                                  const PointRef& pt) const {
  const ModelInfo& info = nlp.info();
  Sample s{pt, {}, {}, {}, {}, std::vector<double>(info.states.size()),
           std::vector<double>(info.inputs.size()), std::vector<double>(info.parameters.size())};
  nlp.point_state(v, pt, s.x);
  nlp.point_inputs(v, pt, s.u);
  nlp.parameters(v, s.p);
  const auto nb = Eigen::Index(base_states_), nj = Eigen::Index(parameters_.size()),
             nm = Eigen::Index(m_.outputs.size());
  s.s_x.resize(nb, nj);
  for (Eigen::Index i = 0; i < nb; ++i)
    for (Eigen::Index j = 0; j < nj; ++j) {
      const int k = sensitivity_state_[std::size_t(i)][std::size_t(j)];
      s.s_x(i, j) = k < 0 ? 0.0 : s.x[std::size_t(k)];  // missing: structurally zero
    }
  Model& model = nlp.model(pt.experiment);
  Eigen::MatrixXd hx = dense_jacobian(model, Jacobian::h_x, pt.time, s.x, s.u, s.p);
  Eigen::MatrixXd hp = dense_jacobian(model, Jacobian::h_p, pt.time, s.x, s.u, s.p);
  s.h_x.resize(nm, nb);
  s.h_p.resize(nm, nj);
  for (Eigen::Index r = 0; r < nm; ++r) {
    s.h_x.row(r) = hx.row(Eigen::Index(m_.outputs[r])).head(nb);
    for (Eigen::Index j = 0; j < nj; ++j) s.h_p(r, j) = hp(Eigen::Index(m_.outputs[r]), Eigen::Index(parameters_[j]));
  }
  s.s_y = s.h_x * s.s_x + s.h_p;
  return s;
}

Eigen::MatrixXd FisherEvaluator::fisher(CollocationNlp& nlp, std::span<const double> v) const {
  Eigen::VectorXd w(Eigen::Index(m_.sigma.size()));
  for (Eigen::Index r = 0; r < w.size(); ++r) w[r] = 1.0 / (m_.sigma[r] * m_.sigma[r]);
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(size(), size());
  for (const PointRef& pt : points_) {
    Sample s = evaluate(nlp, v, pt);
    f += s.s_y.transpose() * w.asDiagonal() * s.s_y;
  }
  return f;
}

Eigen::VectorXd FisherEvaluator::curvature(CollocationNlp& nlp, const Sample& s,
                                           const Eigen::VectorXd& mu, std::size_t j) const {
  const std::size_t nx = s.x.size(), nu = s.u.size();
  Eigen::VectorXd dir = Eigen::VectorXd::Zero(Eigen::Index(nx + nu + s.p.size()));
  for (std::size_t i = 0; i < base_states_; ++i) dir[Eigen::Index(i)] = s.s_x(Eigen::Index(i), Eigen::Index(j));
  dir[Eigen::Index(nx + nu + parameters_[j])] = 1.0;
  Model& model = nlp.model(s.point.experiment);
  if (mu.isZero(0.0)) return Eigen::VectorXd::Zero(dir.size());
  double scale = 1.0;
  for (double z : s.x) scale = std::max(scale, std::abs(z));
  for (double z : s.p) scale = std::max(scale, std::abs(z));
  const double eps = 1e-6 * scale / dir.cwiseAbs().maxCoeff();
  auto shifted = [&](double sign) {
    std::vector<double> x = s.x, u = s.u, p = s.p;
    for (std::size_t i = 0; i < nx; ++i) x[i] += sign * eps * dir[Eigen::Index(i)];
    for (std::size_t i = 0; i < p.size(); ++i) p[i] += sign * eps * dir[Eigen::Index(nx + nu + i)];
    return output_gradient(model, s.point.time, x, u, p, mu);
  };
  return (shifted(1.0) - shifted(-1.0)) / (2.0 * eps);
}

void FisherEvaluator::add_gradient(CollocationNlp& nlp, std::span<const double> v,
                                   const Eigen::MatrixXd& g, std::span<double> grad) const {
  const ModelInfo& info = nlp.info();
  Eigen::VectorXd w(Eigen::Index(m_.sigma.size()));
  for (Eigen::Index r = 0; r < w.size(); ++r) w[r] = 1.0 / (m_.sigma[r] * m_.sigma[r]);
  const auto nz = Eigen::Index(info.states.size() + info.inputs.size() + info.parameters.size());
  for (const PointRef& pt : points_) {
    Sample s = evaluate(nlp, v, pt);
    Eigen::MatrixXd lambda = 2.0 * w.asDiagonal() * s.s_y * g;  // ∂tr(GF)/∂S_y
    Eigen::MatrixXd d_sx = s.h_x.transpose() * lambda;
    Eigen::VectorXd grad_z = Eigen::VectorXd::Zero(nz);
    for (std::size_t i = 0; i < base_states_; ++i)
      for (std::size_t j = 0; j < parameters_.size(); ++j)
        if (sensitivity_state_[i][j] >= 0)
          grad_z[sensitivity_state_[i][j]] += d_sx(Eigen::Index(i), Eigen::Index(j));
    for (std::size_t j = 0; j < parameters_.size(); ++j) {
      Eigen::VectorXd mu = Eigen::VectorXd::Zero(Eigen::Index(info.outputs.size()));
      for (std::size_t r = 0; r < m_.outputs.size(); ++r)
        mu[Eigen::Index(m_.outputs[r])] += lambda(Eigen::Index(r), Eigen::Index(j));
      grad_z += curvature(nlp, s, mu, j);
    }
    add_mapped_gradient(nlp, pt, grad_z, grad);
  }
}

// --- A, T, D -------------------------------------------------------------------

double FisherCriterion::value(CollocationNlp& nlp, std::span<const double> v) {
  double information = criterion_information(criterion_, fisher_->fisher(nlp, v));
  return -information;  // NaN (not positive definite) becomes an evaluation error
}

void FisherCriterion::gradient(CollocationNlp& nlp, std::span<const double> v,
                               std::span<double> g) {
  Eigen::MatrixXd f = fisher_->fisher(nlp, v);
  Eigen::MatrixXd weight;
  switch (criterion_) {
  case DesignCriterion::T: weight = -Eigen::MatrixXd::Identity(f.rows(), f.cols()); break;
  case DesignCriterion::D: weight = -f.inverse(); break;                  // −∂ log det F/∂F
  case DesignCriterion::A: weight = -(f.inverse() * f.inverse()); break;  // ∂ tr F⁻¹/∂F
  case DesignCriterion::E:
    throw std::logic_error("internal error: the E criterion is an epigraph, not an objective");
  }
  fisher_->add_gradient(nlp, v, weight, g);
}

// --- E -------------------------------------------------------------------------

FisherEpigraph::FisherEpigraph(CollocationNlp& nlp, std::shared_ptr<const FisherEvaluator> fisher)
    : fisher_(std::move(fisher)) {
  const int n = fisher_->size();
  Eigen::MatrixXd f0 = fisher_->fisher(nlp, nlp.initial_guess());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(f0);
  double lmin = eig.eigenvalues().minCoeff(), lmax = eig.eigenvalues().maxCoeff();
  double s0 = lmin > 0.0 ? 0.5 * lmin : lmin - 1e-3 * (1.0 + std::abs(lmax));
  Eigen::LLT<Eigen::MatrixXd> llt(f0 - s0 * Eigen::MatrixXd::Identity(n, n));
  Eigen::MatrixXd l0 = llt.info() == Eigen::Success ? Eigen::MatrixXd(llt.matrixL())
                                                     : Eigen::MatrixXd::Identity(n, n);
  s_ = nlp.add_variables(1, {}, s0);
  l_ = nlp.add_variables(n * (n + 1) / 2, {}, 0.0);
  std::vector<double> guess = nlp.initial_guess();
  for (int a = 0; a < n; ++a)
    for (int c = 0; c <= a; ++c) guess[std::size_t(l_var(a, c))] = l0(a, c);
  nlp.set_initial_guess(std::move(guess));
  row_scale_ = 1.0 / std::max(1.0, f0.cwiseAbs().maxCoeff());
}

int FisherEpigraph::rows() const { return fisher_->size() * (fisher_->size() + 1) / 2; }

void FisherEpigraph::bounds(std::span<double> lo, std::span<double> hi) const {
  std::fill(lo.begin(), lo.end(), 0.0);
  std::fill(hi.begin(), hi.end(), 0.0);
}

void FisherEpigraph::scaling(std::span<double> s) const {
  std::fill(s.begin(), s.end(), row_scale_);
}

void FisherEpigraph::values(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) {
  Eigen::MatrixXd f = fisher_->fisher(nlp, v);
  for (int a = 0; a < fisher_->size(); ++a)
    for (int b = 0; b <= a; ++b) {
      double llt = 0.0;
      for (int c = 0; c <= b; ++c) llt += v[std::size_t(l_var(a, c))] * v[std::size_t(l_var(b, c))];
      g[std::size_t(a * (a + 1) / 2 + b)] = f(a, b) - (a == b ? v[std::size_t(s_)] : 0.0) - llt;
    }
}

void FisherEpigraph::jacobian(CollocationNlp& nlp, std::span<const double> v, int row0,
                              SparseAssembler& jac) {
  const int n = fisher_->size();
  std::vector<double> grad(v.size());
  for (int a = 0; a < n; ++a)
    for (int b = 0; b <= a; ++b) {
      const int row = row0 + a * (a + 1) / 2 + b;
      std::fill(grad.begin(), grad.end(), 0.0);
      fisher_->add_gradient(nlp, v, symmetric_unit(n, a, b), grad);
      for (int var : fisher_->variables()) jac.add(row, var, grad[std::size_t(var)]);
      if (a == b) jac.add(row, s_, -1.0);
      for (int c = 0; c <= b; ++c) {
        jac.add(row, l_var(a, c), -v[std::size_t(l_var(b, c))]);
        jac.add(row, l_var(b, c), -v[std::size_t(l_var(a, c))]);
      }
    }
}

}  // namespace mo::runtime::detail
