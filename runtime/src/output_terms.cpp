#include "output_terms.hpp"

#include <cmath>
#include <set>

namespace mo::runtime::detail {
namespace {

bool provides_output_hessian(const CollocationNlp& nlp) {
  return nlp.model(0).provides_hessian(Hessian::h);
}

// Adds scale·H (dense over z-indices `cols`, symmetric) through the point's variable map.
void add_dense_hessian(const CollocationNlp& nlp, const PointRef& pt, const std::vector<int>& cols,
                       const Eigen::MatrixXd& h, double scale, SparseAssembler& hess) {
  VariableMap map = nlp.variable_map(pt);
  for (std::size_t a = 0; a < cols.size(); ++a)
    for (std::size_t b = 0; b < cols.size(); ++b)
      for (auto [va, ca] : map[std::size_t(cols[a])])
        for (auto [vb, cb] : map[std::size_t(cols[b])])
          if (va >= vb) hess.add(va, vb, scale * h(Eigen::Index(a), Eigen::Index(b)) * ca * cb);
}

}  // namespace

std::vector<std::vector<int>> all_output_dependencies(const Model& model) {
  const ModelInfo& info = model.info();
  const int nx = int(info.states.size()), nu = int(info.inputs.size());
  std::vector<std::vector<int>> deps(info.outputs.size());
  auto scan = [&](Jacobian block, int offset) {
    const Sparsity& sp = model.jacobian_sparsity(block);
    for (int c = 0; c < sp.cols; ++c)
      for (int e = sp.col_start[c]; e < sp.col_start[c + 1]; ++e)
        deps[std::size_t(sp.row_index[e])].push_back(offset + c);
  };
  scan(Jacobian::h_x, 0);  // columns ascending: x, then u, then p
  scan(Jacobian::h_u, nx);
  scan(Jacobian::h_p, nx + nu);
  return deps;
}

void add_mapped_gradient(const CollocationNlp& nlp, const PointRef& pt,
                         const Eigen::VectorXd& grad_z, std::span<double> g) {
  VariableMap map = nlp.variable_map(pt);
  for (std::size_t a = 0; a < map.size(); ++a)
    if (grad_z[Eigen::Index(a)] != 0.0)
      for (auto [var, coeff] : map[a]) g[std::size_t(var)] += coeff * grad_z[Eigen::Index(a)];
}

// --- weighted outputs ----------------------------------------------------------

double WeightedOutputs::value(CollocationNlp& nlp, std::span<const double> v) {
  double sum = 0.0;
  for (const OutputAtPoint& t : terms_) sum += t.weight * nlp.outputs(v, t.point)[t.output];
  return sum;
}

void WeightedOutputs::gradient(CollocationNlp& nlp, std::span<const double> v,
                               std::span<double> g) {
  for (const OutputAtPoint& t : terms_) {
    const auto j = nlp.output_jacobian(v, t.point);
    const Eigen::VectorXd row = t.weight * Eigen::VectorXd(j.row(Eigen::Index(t.output)).transpose());
    add_mapped_gradient(nlp, t.point, row, g);
  }
}

bool WeightedOutputs::has_hessian(const CollocationNlp& nlp) const {
  return provides_output_hessian(nlp);
}

void WeightedOutputs::hessian(CollocationNlp& nlp, std::span<const double> v, double factor,
                              SparseAssembler& hess) {
  std::vector<double> mu(nlp.info().outputs.size());
  for (const OutputAtPoint& t : terms_) {
    std::fill(mu.begin(), mu.end(), 0.0);
    mu[t.output] = t.weight;
    nlp.add_model_hessian(Hessian::h, v, t.point, mu, factor, hess);
  }
}

// --- least squares -------------------------------------------------------------

double LeastSquares::value(CollocationNlp& nlp, std::span<const double> v) {
  double sum = 0.0;
  for (const MeasuredSample& s : samples_) {
    std::vector<double> y = nlp.outputs(v, s.point);
    for (std::size_t k = 0; k < y.size(); ++k)
      if (!std::isnan(s.measured[k])) sum += std::pow((y[k] - s.measured[k]) / s.sigma[k], 2);
  }
  return sum;
}

void LeastSquares::gradient(CollocationNlp& nlp, std::span<const double> v, std::span<double> g) {
  for (const MeasuredSample& s : samples_) {
    std::vector<double> y = nlp.outputs(v, s.point);
    const auto j = nlp.output_jacobian(v, s.point);
    Eigen::VectorXd grad_z = Eigen::VectorXd::Zero(j.cols());
    for (std::size_t k = 0; k < y.size(); ++k)
      if (!std::isnan(s.measured[k]))
        grad_z += 2.0 * (y[k] - s.measured[k]) / std::pow(s.sigma[k], 2) *
                  Eigen::VectorXd(j.row(Eigen::Index(k)).transpose());
    add_mapped_gradient(nlp, s.point, grad_z, g);
  }
}

bool LeastSquares::has_hessian(const CollocationNlp& nlp) const {
  return provides_output_hessian(nlp);
}

void LeastSquares::hessian(CollocationNlp& nlp, std::span<const double> v, double factor,
                           SparseAssembler& hess) {
  const std::size_t ny = nlp.info().outputs.size();
  const std::vector<std::vector<int>> deps = all_output_dependencies(nlp.model(0));
  for (const MeasuredSample& s : samples_) {
    std::vector<double> y = nlp.outputs(v, s.point);
    const auto j = nlp.output_jacobian(v, s.point);
    std::set<int> col_set;
    std::vector<double> mu(ny, 0.0);
    for (std::size_t k = 0; k < ny; ++k)
      if (!std::isnan(s.measured[k])) {
        col_set.insert(deps[k].begin(), deps[k].end());
        mu[k] = 2.0 * (y[k] - s.measured[k]) / std::pow(s.sigma[k], 2);
      }
    std::vector<int> cols(col_set.begin(), col_set.end());
    Eigen::MatrixXd gn = Eigen::MatrixXd::Zero(Eigen::Index(cols.size()), Eigen::Index(cols.size()));
    for (std::size_t k = 0; k < ny; ++k) {
      if (std::isnan(s.measured[k])) continue;
      Eigen::VectorXd row(Eigen::Index(cols.size()));
      for (std::size_t a = 0; a < cols.size(); ++a) row[Eigen::Index(a)] = j.coeff(Eigen::Index(k), cols[a]);
      gn += 2.0 / std::pow(s.sigma[k], 2) * row * row.transpose();
    }
    add_dense_hessian(nlp, s.point, cols, gn, factor, hess);
    nlp.add_model_hessian(Hessian::h, v, s.point, mu, factor, hess);
  }
}

// --- output constraints --------------------------------------------------------

OutputConstraints::OutputConstraints(std::vector<OutputAtPoint> rows) : rows_(std::move(rows)) {
  std::map<std::tuple<int, int, double>, std::size_t> group;  // (experiment, element, τ) → at_point_ index
  for (std::size_t r = 0; r < rows_.size(); ++r) {
    const PointRef& p = rows_[r].point;
    const auto [it, fresh] = group.try_emplace({p.experiment, p.element, p.tau}, at_point_.size());
    if (fresh) at_point_.emplace_back();
    at_point_[it->second].push_back(r);
  }
}

void OutputConstraints::bounds(std::span<double> lo, std::span<double> hi) const {
  for (std::size_t r = 0; r < rows_.size(); ++r) lo[r] = rows_[r].bounds.lo, hi[r] = rows_[r].bounds.hi;
}

void OutputConstraints::values(CollocationNlp& nlp, std::span<const double> v,
                               std::span<double> g) {
  for (const auto& rows : at_point_) {
    const std::vector<double> y = nlp.outputs(v, rows_[rows.front()].point);
    for (std::size_t r : rows) g[r] = y[rows_[r].output];
  }
}

void OutputConstraints::jacobian(CollocationNlp& nlp, std::span<const double> v, int row0,
                                 SparseAssembler& jac) {
  for (const auto& rows : at_point_) {
    const PointRef& pt = rows_[rows.front()].point;
    const auto j = nlp.output_jacobian(v, pt);
    const VariableMap map = nlp.variable_map(pt);
    for (std::size_t r : rows) {
      const std::size_t k = rows_[r].output;
      if (dependencies_.empty()) dependencies_ = all_output_dependencies(nlp.model(0));
      for (int z : dependencies_[k])
        for (auto [var, coeff] : map[std::size_t(z)])
          jac.add(row0 + int(r), var, coeff * j.coeff(Eigen::Index(k), z));
    }
  }
}

bool OutputConstraints::has_hessian(const CollocationNlp& nlp) const {
  return provides_output_hessian(nlp);
}

void OutputConstraints::hessian(CollocationNlp& nlp, std::span<const double> v,
                                std::span<const double> lambda, SparseAssembler& hess) {
  std::vector<double> mu(nlp.info().outputs.size());
  for (const auto& rows : at_point_) {
    std::fill(mu.begin(), mu.end(), 0.0);
    for (std::size_t r : rows) mu[rows_[r].output] += lambda[r];
    nlp.add_model_hessian(Hessian::h, v, rows_[rows.front()].point, mu, 1.0, hess);
  }
}

}  // namespace mo::runtime::detail
