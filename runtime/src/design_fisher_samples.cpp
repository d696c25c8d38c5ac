// Measurement samples of a design and their quadratic forms; see design_fisher_samples.hpp.
#include "design_fisher_samples.hpp"

#include "mo/runtime/model.hpp"
#include "output_terms.hpp"

#include <algorithm>
#include <set>

namespace mo::runtime::detail {

std::optional<std::vector<std::vector<std::size_t>>> sensitivity_outputs(
    const ModelInfo& info, const MeasurementDesign& m, const std::vector<std::size_t>& parameters) {
  std::vector<std::vector<std::size_t>> out;
  for (std::size_t y : m.outputs) {
    if (y >= info.outputs.size()) return std::nullopt;
    out.emplace_back();
    for (std::size_t a : parameters) {
      if (a >= info.parameters.size()) return std::nullopt;
      // The compiler's name for ∂y/∂p (symbolic::sensitivity_name).
      auto k = info.output_index("d(" + info.outputs[y].name + ")/d(" + info.parameters[a].name + ")");
      if (!k) return std::nullopt;
      out.back().push_back(*k);
    }
  }
  return out;
}

FisherSamples::FisherSamples(const CollocationNlp& nlp, const MeasurementDesign& m,
                             std::vector<std::vector<std::size_t>> sensitivity_outputs)
    : sens_(std::move(sensitivity_outputs)), num_outputs_(nlp.info().outputs.size()) {
  if (sens_.empty() || sens_.front().empty())
    throw ProblemError("input design needs measured outputs and parameters");
  n_ = int(sens_.front().size());
  for (double s : m.sigma) {
    if (!(s > 0.0)) throw ProblemError("measured output sigma not positive");
    weight_.push_back(1.0 / (s * s));
  }
  const ExperimentSetup& ex = nlp.experiment(0);
  for (double t : m.times) {
    if (t < ex.t0 || t > ex.tf) throw ProblemError("measurement time outside [t0, tf]");
    points_.push_back(nlp.point_at(0, t));
  }
  std::set<int> deps;
  for (const auto& row : sens_)
    for (std::size_t out : row)
      for (int z : output_dependencies(nlp.model(0), out)) deps.insert(z);
  deps_.assign(deps.begin(), deps.end());
  auto position = [&](int z) {
    return int(std::lower_bound(deps_.begin(), deps_.end(), z) - deps_.begin());
  };
  of_.resize(sens_.size());
  for (std::size_t r = 0; r < sens_.size(); ++r)
    for (std::size_t out : sens_[r]) {
      of_[r].emplace_back();
      for (int z : output_dependencies(nlp.model(0), out)) of_[r].back().push_back(position(z));
    }
}

std::vector<int> FisherSamples::columns(int a, int b) const {
  std::set<int> cols;
  for (const auto& r : of_) {
    cols.insert(r[std::size_t(a)].begin(), r[std::size_t(a)].end());
    cols.insert(r[std::size_t(b)].begin(), r[std::size_t(b)].end());
  }
  std::vector<int> out;
  for (int c : cols) out.push_back(deps_[std::size_t(c)]);
  return out;
}

void FisherSamples::set_pattern(const std::vector<std::pair<int, int>>& coupled) {
  std::set<std::pair<int, int>> pairs;
  for (auto [a, b] : coupled)
    for (const auto& r : of_)
      for (int c : r[std::size_t(a)])
        for (int d : r[std::size_t(b)]) pairs.insert({std::max(c, d), std::min(c, d)});
  gn_pairs_.assign(pairs.begin(), pairs.end());
}

Eigen::MatrixXd FisherSamples::sensitivities(CollocationNlp& nlp, std::span<const double> v,
                                             const PointRef& pt) const {
  std::vector<double> y = nlp.outputs(v, pt);
  Eigen::MatrixXd s(Eigen::Index(sens_.size()), n_);
  for (std::size_t r = 0; r < sens_.size(); ++r)
    for (int a = 0; a < n_; ++a) s(Eigen::Index(r), a) = y[sens_[r][std::size_t(a)]];
  return s;
}

Eigen::MatrixXd FisherSamples::sensitivity_jacobian(const Eigen::MatrixXd& j, std::size_t r) const {
  const auto nd = Eigen::Index(deps_.size());
  Eigen::MatrixXd jr(n_, nd);
  for (int a = 0; a < n_; ++a)
    for (Eigen::Index c = 0; c < nd; ++c) jr(a, c) = j(Eigen::Index(sens_[r][std::size_t(a)]), deps_[std::size_t(c)]);
  return jr;
}

Eigen::MatrixXd FisherSamples::fisher(CollocationNlp& nlp, std::span<const double> v) const {
  Eigen::Map<const Eigen::VectorXd> w(weight_.data(), Eigen::Index(weight_.size()));
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(n_, n_);
  for (const PointRef& pt : points_) {
    Eigen::MatrixXd s = sensitivities(nlp, v, pt);
    f += s.transpose() * w.asDiagonal() * s;
  }
  return f;
}

Eigen::VectorXd FisherSamples::product_gradient(const Eigen::MatrixXd& s, const Eigen::MatrixXd& j,
                                                int a, int b, const std::vector<int>& cols) const {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(Eigen::Index(cols.size()));
  for (std::size_t k = 0; k < cols.size(); ++k)
    for (std::size_t r = 0; r < sens_.size(); ++r)
      d[Eigen::Index(k)] += weight_[r] * (s(Eigen::Index(r), a) * j(Eigen::Index(sens_[r][std::size_t(b)]), cols[k]) +
                                          s(Eigen::Index(r), b) * j(Eigen::Index(sens_[r][std::size_t(a)]), cols[k]));
  return d;
}

void FisherSamples::add_hessian(CollocationNlp& nlp, std::span<const double> v, const Eigen::MatrixXd& g,
                                double scale, SparseAssembler& hess) const {
  const auto nd = Eigen::Index(deps_.size());
  std::vector<double> mu(num_outputs_);
  each_sample(nlp, v, [&](const PointRef& pt, const Eigen::MatrixXd& s, const Eigen::MatrixXd& j) {
    Eigen::MatrixXd gauss_newton = Eigen::MatrixXd::Zero(nd, nd);
    std::fill(mu.begin(), mu.end(), 0.0);
    for (std::size_t r = 0; r < sens_.size(); ++r) {
      Eigen::MatrixXd jr = sensitivity_jacobian(j, r);
      gauss_newton += 2.0 * scale * weight_[r] * jr.transpose() * g * jr;
      Eigen::VectorXd m = g * s.row(Eigen::Index(r)).transpose();
      for (int a = 0; a < n_; ++a) mu[sens_[r][std::size_t(a)]] += 2.0 * scale * weight_[r] * m[a];
    }
    VariableMap map = nlp.variable_map(pt);
    auto add = [&](int a, int b) {  // both orders of the symmetric term, lower triangle
      for (auto [va, ca] : map[std::size_t(deps_[std::size_t(a)])])
        for (auto [vb, cb] : map[std::size_t(deps_[std::size_t(b)])])
          if (va >= vb) hess.add(va, vb, gauss_newton(a, b) * ca * cb);
    };
    for (auto [a, b] : gn_pairs_) {
      add(a, b);
      if (a != b) add(b, a);
    }
    nlp.add_model_hessian(Hessian::h, v, pt, mu, 1.0, hess);
  });
}

}  // namespace mo::runtime::detail
