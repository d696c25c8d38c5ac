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

namespace {

/// Where z is or would be in `sorted`.
int position(const std::vector<int>& sorted, int z) {
  return int(std::lower_bound(sorted.begin(), sorted.end(), z) - sorted.begin());
}

/// The position of z in `sorted`, −1 if absent.
int find(const std::vector<int>& sorted, int z) {
  const int k = position(sorted, z);
  return k < int(sorted.size()) && sorted[std::size_t(k)] == z ? k : -1;
}

}  // namespace

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
  const std::vector<std::vector<int>> depends = all_output_dependencies(nlp.model(0));
  std::set<int> deps;
  for (const auto& row : sens_) {
    std::set<int> mine;
    for (std::size_t out : row) mine.insert(depends[out].begin(), depends[out].end());
    local_.emplace_back(mine.begin(), mine.end());
    deps.insert(mine.begin(), mine.end());
  }
  deps_.assign(deps.begin(), deps.end());
  of_.resize(sens_.size());
  for (std::size_t r = 0; r < sens_.size(); ++r)
    for (std::size_t out : sens_[r]) {
      of_[r].emplace_back();
      for (int z : depends[out]) of_[r].back().push_back(position(local_[r], z));
    }
  index_columns();
}

void FisherSamples::index_columns() {
  for (int a = 0; a < n_; ++a)
    for (int b = 0; b <= a; ++b) {
      std::set<int> cols;
      for (std::size_t r = 0; r < sens_.size(); ++r)
        for (int c : {a, b})
          for (int i : of_[r][std::size_t(c)]) cols.insert(local_[r][std::size_t(i)]);
      columns_.emplace_back(cols.begin(), cols.end());
      in_columns_.emplace_back();
      for (const std::vector<int>& local : local_) {
        in_columns_.back().emplace_back();
        for (int z : local) in_columns_.back().back().push_back(find(columns_.back(), z));
      }
    }
}

void FisherSamples::set_pattern(const std::vector<std::pair<int, int>>& coupled) {
  std::vector<std::set<std::pair<int, int>>> mine(sens_.size());  // positions (c ≥ d) in local_[r]
  std::set<std::pair<int, int>> pairs;                            // positions in deps_
  auto global = [&](std::size_t r, std::pair<int, int> cd) {
    return std::pair{position(deps_, local_[r][std::size_t(cd.first)]),
                     position(deps_, local_[r][std::size_t(cd.second)])};
  };
  for (std::size_t r = 0; r < sens_.size(); ++r) {
    for (auto [a, b] : coupled)
      for (int c : of_[r][std::size_t(a)])
        for (int d : of_[r][std::size_t(b)]) mine[r].insert({std::max(c, d), std::min(c, d)});
    for (const auto& cd : mine[r]) pairs.insert(global(r, cd));
  }
  gn_pairs_.assign(pairs.begin(), pairs.end());
  gn_local_.assign(sens_.size(), {});
  for (std::size_t r = 0; r < sens_.size(); ++r)
    for (const auto& cd : mine[r]) {
      const auto k = std::lower_bound(gn_pairs_.begin(), gn_pairs_.end(), global(r, cd)) - gn_pairs_.begin();
      gn_local_[r].push_back({std::size_t(k), cd.first, cd.second});
    }
}

Eigen::MatrixXd FisherSamples::sensitivities(CollocationNlp& nlp, std::span<const double> v,
                                             const PointRef& pt) const {
  std::vector<double> y = nlp.outputs(v, pt);
  Eigen::MatrixXd s(Eigen::Index(sens_.size()), n_);
  for (std::size_t r = 0; r < sens_.size(); ++r)
    for (int a = 0; a < n_; ++a) s(Eigen::Index(r), a) = y[sens_[r][std::size_t(a)]];
  return s;
}

FisherSamples::LocalJacobians FisherSamples::local_jacobians(CollocationNlp& nlp, std::span<const double> v,
                                                             const PointRef& pt) const {
  using RowMajor = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  const RowMajor j = nlp.output_jacobian(v, pt);
  LocalJacobians out;
  for (std::size_t r = 0; r < sens_.size(); ++r) {
    Eigen::MatrixXd jr = Eigen::MatrixXd::Zero(n_, Eigen::Index(local_[r].size()));
    for (int a = 0; a < n_; ++a)
      for (RowMajor::InnerIterator it(j, Eigen::Index(sens_[r][std::size_t(a)])); it; ++it)
        if (const int k = find(local_[r], int(it.col())); k >= 0) jr(a, k) = it.value();
    out.push_back(std::move(jr));
  }
  return out;
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

Eigen::VectorXd FisherSamples::product_gradient(const Eigen::MatrixXd& s, const LocalJacobians& j, int a,
                                                int b) const {
  const std::vector<std::vector<int>>& in = in_columns_[packed(a, b)];
  Eigen::VectorXd d = Eigen::VectorXd::Zero(Eigen::Index(columns(a, b).size()));
  for (std::size_t r = 0; r < sens_.size(); ++r)
    for (std::size_t i = 0; i < in[r].size(); ++i)
      if (in[r][i] >= 0)
        d[in[r][i]] += weight_[r] * (s(Eigen::Index(r), a) * j[r](b, Eigen::Index(i)) +
                                     s(Eigen::Index(r), b) * j[r](a, Eigen::Index(i)));
  return d;
}

void FisherSamples::add_hessian(CollocationNlp& nlp, std::span<const double> v, const Eigen::MatrixXd& g,
                                double scale, SparseAssembler& hess) const {
  std::vector<double> mu(num_outputs_);
  each_sample(nlp, v, [&](const PointRef& pt, const Eigen::MatrixXd& s, const LocalJacobians& j) {
    // The Gauss–Newton term at (c, d) and at (d, c) of each pair of gn_pairs_.
    std::vector<double> lower(gn_pairs_.size(), 0.0), upper(gn_pairs_.size(), 0.0);
    std::fill(mu.begin(), mu.end(), 0.0);
    for (std::size_t r = 0; r < sens_.size(); ++r) {
      const Eigen::MatrixXd gauss_newton = 2.0 * scale * weight_[r] * j[r].transpose() * g * j[r];
      for (const LocalPair& q : gn_local_[r])
        lower[q.pair] += gauss_newton(q.c, q.d), upper[q.pair] += gauss_newton(q.d, q.c);
      Eigen::VectorXd m = g * s.row(Eigen::Index(r)).transpose();
      for (int a = 0; a < n_; ++a) mu[sens_[r][std::size_t(a)]] += 2.0 * scale * weight_[r] * m[a];
    }
    VariableMap map = nlp.variable_map(pt);
    auto add = [&](int a, int b, double value) {  // lower triangle
      for (auto [va, ca] : map[std::size_t(deps_[std::size_t(a)])])
        for (auto [vb, cb] : map[std::size_t(deps_[std::size_t(b)])])
          if (va >= vb) hess.add(va, vb, value * ca * cb);
    };
    for (std::size_t k = 0; k < gn_pairs_.size(); ++k) {
      const auto [a, b] = gn_pairs_[k];
      add(a, b, lower[k]);
      if (a != b) add(b, a, upper[k]);
    }
    nlp.add_model_hessian(Hessian::h, v, pt, mu, 1.0, hess);
  });
}

}  // namespace mo::runtime::detail
