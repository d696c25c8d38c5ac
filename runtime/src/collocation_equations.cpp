#include "collocation_equations.hpp"

namespace mo::runtime::detail {

CollocationEquations::CollocationEquations(const CollocationNlp& nlp, int experiment)
    : e_(experiment), nx_(int(nlp.info().states.size())), k_(nlp.num_points()),
      n_e_(nlp.num_elements()) {
  nominal_ = nlp.state_nominal(experiment);
}

int CollocationEquations::rows() const { return nx_ + n_e_ * (k_ + 1) * nx_; }

void CollocationEquations::bounds(std::span<double> lo, std::span<double> hi) const {
  std::fill(lo.begin(), lo.end(), 0.0);
  std::fill(hi.begin(), hi.end(), 0.0);
}

void CollocationEquations::scaling(std::span<double> s) const {
  for (std::size_t r = 0; r < s.size(); ++r) s[r] = 1.0 / nominal_[r % std::size_t(nx_)];
}

void CollocationEquations::values(CollocationNlp& nlp, std::span<const double> v,
                                  std::span<double> g) {
  const ModelInfo& info = nlp.info();
  const auto nx = std::size_t(nx_);
  std::vector<double> x(nx), u(info.inputs.size()), p(info.parameters.size()), f(nx);
  nlp.parameters(v, p);
  nlp.start_values(e_, v, p, x);
  for (std::size_t s = 0; s < nx; ++s) g[s] = v[nlp.state_var(e_, 0, 0, int(s))] - x[s];
  const CollocationPolynomials& poly = nlp.polynomials();
  for (int i = 0; i < n_e_; ++i) {
    const double h = nlp.element_length(e_, i);
    for (int j = 1; j <= k_; ++j) {
      PointRef pt = nlp.point(e_, i, poly.tau[std::size_t(j)]);
      nlp.point_state(v, pt, x);
      nlp.point_inputs(v, pt, u);
      nlp.model(e_).rhs(pt.time, x, u, p, f);
      for (std::size_t s = 0; s < nx; ++s) {
        double sum = -h * f[s];
        for (int k = 0; k <= k_; ++k) sum += poly.derivative(j, k) * v[nlp.state_var(e_, i, k, int(s))];
        g[std::size_t(element_row(i) + (j - 1) * nx_) + s] = sum;
      }
    }
    for (std::size_t s = 0; s < nx; ++s) {
      double sum = v[nlp.state_var(e_, i + 1, 0, int(s))];
      for (int k = 0; k <= k_; ++k) sum -= poly.at_end[std::size_t(k)] * v[nlp.state_var(e_, i, k, int(s))];
      g[std::size_t(element_row(i) + k_ * nx_) + s] = sum;
    }
  }
}

void CollocationEquations::add_sparse_block(CollocationNlp& nlp, Jacobian block,
                                            std::span<const double> v, const PointRef& pt,
                                            int row, double scale, SparseAssembler& jac) {
  Model& m = nlp.model(e_);
  const Sparsity& sp = m.jacobian_sparsity(block);
  std::vector<double> values(std::size_t(sp.nnz()));
  if (sp.nnz() > 0) {
    const ModelInfo& info = nlp.info();
    std::vector<double> x(info.states.size()), u(info.inputs.size()), p(info.parameters.size());
    nlp.point_state(v, pt, x);
    nlp.point_inputs(v, pt, u);
    nlp.parameters(v, p);
    m.jacobian_values(block, pt.time, x, u, p, values);
  }
  VariableMap map = nlp.variable_map(pt);
  const std::size_t nx = nlp.info().states.size(), nu = nlp.info().inputs.size();
  const std::size_t offset = block == Jacobian::f_x ? 0 : block == Jacobian::f_u ? nx : nx + nu;
  for (int c = 0; c < sp.cols; ++c)
    for (int k = sp.col_start[c]; k < sp.col_start[c + 1]; ++k)
      for (auto [var, coeff] : map[offset + std::size_t(c)])
        jac.add(row + sp.row_index[k], var, scale * coeff * values[std::size_t(k)]);
}

void CollocationEquations::jacobian(CollocationNlp& nlp, std::span<const double> v, int row0,
                                    SparseAssembler& jac) {
  for (int s = 0; s < nx_; ++s) jac.add(row0 + s, nlp.state_var(e_, 0, 0, s), 1.0);
  add_sparse_block(nlp, Jacobian::x0_p, v, nlp.point(e_, 0, 0.0), row0, -1.0, jac);
  const CollocationPolynomials& poly = nlp.polynomials();
  for (int i = 0; i < n_e_; ++i) {
    const double h = nlp.element_length(e_, i);
    for (int j = 1; j <= k_; ++j) {
      const int row = row0 + element_row(i) + (j - 1) * nx_;
      for (int s = 0; s < nx_; ++s)
        for (int k = 0; k <= k_; ++k)
          jac.add(row + s, nlp.state_var(e_, i, k, s), poly.derivative(j, k));
      PointRef pt = nlp.point(e_, i, poly.tau[std::size_t(j)]);
      for (Jacobian block : {Jacobian::f_x, Jacobian::f_u, Jacobian::f_p})
        add_sparse_block(nlp, block, v, pt, row, -h, jac);
    }
    const int row = row0 + element_row(i) + k_ * nx_;
    for (int s = 0; s < nx_; ++s) {
      jac.add(row + s, nlp.state_var(e_, i + 1, 0, s), 1.0);
      for (int k = 0; k <= k_; ++k)
        if (poly.at_end[std::size_t(k)] != 0.0)
          jac.add(row + s, nlp.state_var(e_, i, k, s), -poly.at_end[std::size_t(k)]);
    }
  }
}

bool CollocationEquations::has_hessian(const CollocationNlp& nlp) const {
  // The Hessian of x0(p) is not part of the Model interface: exact only if x0 is affine in p.
  return nlp.model(e_).provides_hessian(Hessian::f);
}

void CollocationEquations::hessian(CollocationNlp& nlp, std::span<const double> v,
                                   std::span<const double> lambda, SparseAssembler& hess) {
  const CollocationPolynomials& poly = nlp.polynomials();
  for (int i = 0; i < n_e_; ++i) {
    const double h = nlp.element_length(e_, i);
    for (int j = 1; j <= k_; ++j) {
      auto weights = lambda.subspan(std::size_t(element_row(i) + (j - 1) * nx_), std::size_t(nx_));
      nlp.add_model_hessian(Hessian::f, v, nlp.point(e_, i, poly.tau[std::size_t(j)]), weights, -h,
                            hess);
    }
  }
}

}  // namespace mo::runtime::detail
