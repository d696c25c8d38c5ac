// Hand-written models implementing mo::runtime::Model, standing in for
// generated code in the runtime tests:
//
//   LinearDecay      a' = -k a + u, b' = a; x0 = (a0, 0); y = (a, k b)  — analytic solution
//   CartPendulum     the plant of docs/cart-pendulum.md with hand-derived Jacobians
//   BouncingBall     h' = v, v' = -g; when h < 0: reinit(v, -e pre(v))
//   DoubleIntegrator s' = v, v' = u; y = (u², s, v)  — minimum-energy optimal control
//   WithSensitivities<any model>: appends S = ∂x/∂p as states, der(S) = f_x S + f_p
#pragma once

#include "mo/runtime/model.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <string>
#include <vector>

namespace mo::runtime::fixtures {

/// Dense helper: the CSC values of a dense rows × cols Eigen matrix (column-major already).
inline void copy_dense(const Eigen::MatrixXd& m, std::span<double> values) {
  std::copy(m.data(), m.data() + m.size(), values.begin());
}

inline StateVariable state(std::string name, std::string unit, double start = 0.0) {
  StateVariable s;
  s.name = std::move(name);
  s.unit = std::move(unit);
  s.start = start;
  return s;
}

inline Parameter parameter(std::string name, std::string unit, double value,
                           std::string description = {}) {
  Parameter p;
  p.name = std::move(name);
  p.unit = std::move(unit);
  p.value = value;
  p.description = std::move(description);
  return p;
}

// ---------------------------------------------------------------------------

/// a' = -k a + u, b' = a, a(0) = a0, b(0) = 0; outputs y = (a, k·b).
class LinearDecay final : public Model {
public:
  LinearDecay() {
    info_.name = "LinearDecay";
    info_.states = {state("a", "1", 1.0), state("b", "s")};
    info_.inputs = {{"u", "forcing", "1/s"}};
    info_.outputs = {{"a_out", "", "1"}, {"kb", "", "1"}};
    info_.parameters = {parameter("k", "1/s", 2.0), parameter("a0", "1", 1.0)};
    using P = std::pair<int, int>;
    sp_[0] = Sparsity::from_triplets(2, 2, std::vector<P>{{0, 0}, {1, 0}});  // f_x
    sp_[1] = Sparsity::from_triplets(2, 1, std::vector<P>{{0, 0}});          // f_u
    sp_[2] = Sparsity::from_triplets(2, 2, std::vector<P>{{0, 0}});          // f_p
    sp_[3] = Sparsity::from_triplets(2, 2, std::vector<P>{{0, 0}, {1, 1}});  // h_x
    sp_[4] = Sparsity::empty(2, 1);                                          // h_u
    sp_[5] = Sparsity::from_triplets(2, 2, std::vector<P>{{1, 0}});          // h_p
    sp_[6] = Sparsity::from_triplets(2, 2, std::vector<P>{{0, 1}});          // x0_p
    // Hessian of λᵀf in z = (a, b, u, k, a0): only ∂²(-λ0 k a)/∂k∂a = -λ0.
    hf_ = Sparsity::from_triplets(5, 5, std::vector<P>{{3, 0}});
    // Hessian of μᵀh: ∂²(μ1 k b)/∂k∂b = μ1.
    hh_ = Sparsity::from_triplets(5, 5, std::vector<P>{{3, 1}});
  }
  const ModelInfo& info() const override { return info_; }
  std::unique_ptr<Model> clone() const override { return std::make_unique<LinearDecay>(*this); }
  void initial_state(double, std::span<const double>, std::span<const double> p, std::span<double> x0) override {
    x0[0] = p[1];
    x0[1] = 0.0;
  }
  void rhs(double, std::span<const double> x, std::span<const double> u,
           std::span<const double> p, std::span<double> xdot) override {
    xdot[0] = -p[0] * x[0] + u[0];
    xdot[1] = x[0];
  }
  void outputs(double, std::span<const double> x, std::span<const double>,
               std::span<const double> p, std::span<double> y) override {
    y[0] = x[0];
    y[1] = p[0] * x[1];
  }
  const Sparsity& jacobian_sparsity(Jacobian block) const override {
    return sp_[static_cast<int>(block)];
  }
  void jacobian_values(Jacobian block, double, std::span<const double> x,
                       std::span<const double>, std::span<const double> p,
                       std::span<double> v) override {
    switch (block) {
    case Jacobian::f_x: v[0] = -p[0], v[1] = 1.0; return;
    case Jacobian::f_u: v[0] = 1.0; return;
    case Jacobian::f_p: v[0] = -x[0]; return;
    case Jacobian::h_x: v[0] = 1.0, v[1] = p[0]; return;
    case Jacobian::h_u: return;
    case Jacobian::h_p: v[0] = x[1]; return;
    case Jacobian::x0_p: v[0] = 1.0; return;
    }
  }
  bool provides_hessian(Hessian) const override { return true; }
  const Sparsity& hessian_sparsity(Hessian which) const override {
    return which == Hessian::f ? hf_ : hh_;
  }
  void hessian_values(Hessian which, double, std::span<const double>, std::span<const double>,
                      std::span<const double>, std::span<const double> w,
                      std::span<double> v) override {
    v[0] = which == Hessian::f ? -w[0] : w[1];
  }

private:
  ModelInfo info_;
  Sparsity sp_[7];
  Sparsity hf_, hh_;
};

// ---------------------------------------------------------------------------

/// The cart-pendulum plant of docs/cart-pendulum.md: x = (x, phi, v, w), u = F,
/// p = (m1, d1, m2, d2, l), y = (x, phi). With M(phi)·[v', w'] = b(x, F, p), every
/// derivative of the accelerations a = M⁻¹b follows from ∂a = M⁻¹(∂b − ∂M·a).
class CartPendulum final : public Model {
public:
  static constexpr double gravity = 9.81;

  CartPendulum() {
    info_.name = "CartPendulum";
    info_.states = {state("x", "m"), state("phi", "rad"), state("v", "m/s"), state("w", "rad/s")};
    info_.states[0].min = -1.0, info_.states[0].max = 1.0;
    info_.inputs = {{"F", "force on the cart", "N"}};
    info_.outputs = {{"y_x", "cart position", "m"}, {"y_phi", "pendulum angle", "rad"}};
    info_.parameters = {parameter("m1", "kg", 2.0, "equivalent cart mass"),
                        parameter("d1", "N.s/m", 15.0, "cart friction"),
                        parameter("m2", "kg", 1.0, "pendulum mass"),
                        parameter("d2", "N.m.s/rad", 0.5, "pendulum friction"),
                        parameter("l", "m", 0.5, "pendulum length")};
    using P = std::pair<int, int>;
    sp_[0] = Sparsity::from_triplets(
        4, 4, std::vector<P>{{2, 1}, {3, 1}, {0, 2}, {2, 2}, {3, 2}, {1, 3}, {2, 3}, {3, 3}});
    sp_[1] = Sparsity::from_triplets(4, 1, std::vector<P>{{2, 0}, {3, 0}});
    std::vector<P> fp;
    for (int j = 0; j < 5; ++j) fp.insert(fp.end(), {P{2, j}, P{3, j}});
    sp_[2] = Sparsity::from_triplets(4, 5, fp);
    sp_[3] = Sparsity::from_triplets(2, 4, std::vector<P>{{0, 0}, {1, 1}});
    sp_[4] = Sparsity::empty(2, 1);
    sp_[5] = Sparsity::empty(2, 5);
    sp_[6] = Sparsity::empty(4, 5);
    // λᵀf is nonlinear in everything except the cart position x: dense lower
    // triangle in z = (x, phi, v, w, F, m1, d1, m2, d2, l) minus x's row/column.
    std::vector<P> hf;
    for (int c = 1; c < 10; ++c)
      for (int r = c; r < 10; ++r) hf.emplace_back(r, c);
    hf_ = Sparsity::from_triplets(10, 10, hf);
    hh_ = Sparsity::empty(10, 10);
  }
  const ModelInfo& info() const override { return info_; }
  std::unique_ptr<Model> clone() const override { return std::make_unique<CartPendulum>(*this); }
  void initial_state(double, std::span<const double>, std::span<const double>, std::span<double> x0) override {
    std::fill(x0.begin(), x0.end(), 0.0);
  }
  void rhs(double, std::span<const double> x, std::span<const double> u,
           std::span<const double> p, std::span<double> xdot) override {
    Eigen::Vector2d a = accelerations(x, u[0], p);
    xdot[0] = x[2];
    xdot[1] = x[3];
    xdot[2] = a[0];
    xdot[3] = a[1];
  }
  void outputs(double, std::span<const double> x, std::span<const double>,
               std::span<const double>, std::span<double> y) override {
    y[0] = x[0];
    y[1] = x[1];
  }
  const Sparsity& jacobian_sparsity(Jacobian block) const override {
    return sp_[static_cast<int>(block)];
  }
  void jacobian_values(Jacobian block, double, std::span<const double> x,
                       std::span<const double> u, std::span<const double> p,
                       std::span<double> v) override {
    switch (block) {
    case Jacobian::f_x: {
      Eigen::Matrix<double, 2, 10> da = acceleration_derivatives(x, u[0], p);
      // columns phi: (2,3); v: (0, 2,3); w: (1, 2,3)
      v[0] = da(0, 1), v[1] = da(1, 1);
      v[2] = 1.0, v[3] = da(0, 2), v[4] = da(1, 2);
      v[5] = 1.0, v[6] = da(0, 3), v[7] = da(1, 3);
      return;
    }
    case Jacobian::f_u: {
      Eigen::Matrix<double, 2, 10> da = acceleration_derivatives(x, u[0], p);
      v[0] = da(0, 4), v[1] = da(1, 4);
      return;
    }
    case Jacobian::f_p: {
      Eigen::Matrix<double, 2, 10> da = acceleration_derivatives(x, u[0], p);
      for (int j = 0; j < 5; ++j) v[2 * j] = da(0, 5 + j), v[2 * j + 1] = da(1, 5 + j);
      return;
    }
    case Jacobian::h_x: v[0] = 1.0, v[1] = 1.0; return;
    case Jacobian::h_u:
    case Jacobian::h_p:
    case Jacobian::x0_p: return;
    }
  }

  // Hessian of λᵀf by central differences of the hand Jacobian (fixture only).
  bool provides_hessian(Hessian) const override { return true; }
  const Sparsity& hessian_sparsity(Hessian which) const override {
    return which == Hessian::f ? hf_ : hh_;
  }
  void hessian_values(Hessian which, double, std::span<const double> x,
                      std::span<const double> u, std::span<const double> p,
                      std::span<const double> w, std::span<double> v) override {
    if (which == Hessian::h) return;  // h is linear
    Eigen::Matrix<double, 10, 1> z;
    z << x[0], x[1], x[2], x[3], u[0], p[0], p[1], p[2], p[3], p[4];
    auto gradient = [&](const Eigen::Matrix<double, 10, 1>& at) {  // ∇_z (λᵀf)
      std::span<const double> zs(at.data(), 10);
      Eigen::Matrix<double, 2, 10> da = acceleration_derivatives(zs.subspan(0, 4), at[4],
                                                                 zs.subspan(5, 5));
      Eigen::Matrix<double, 10, 1> g = w[2] * da.row(0).transpose() + w[3] * da.row(1).transpose();
      g[2] += w[0];
      g[3] += w[1];
      return g;
    };
    Eigen::Matrix<double, 10, 10> hess;
    for (int c = 0; c < 10; ++c) {
      double step = 1e-5 * std::max(1.0, std::abs(z[c]));
      Eigen::Matrix<double, 10, 1> plus = z, minus = z;
      plus[c] += step;
      minus[c] -= step;
      hess.col(c) = (gradient(plus) - gradient(minus)) / (2.0 * step);
    }
    hess = 0.5 * (hess + hess.transpose()).eval();
    for (int c = 0; c < hf_.cols; ++c)
      for (int k = hf_.col_start[c]; k < hf_.col_start[c + 1]; ++k) v[k] = hess(hf_.row_index[k], c);
  }

  /// (v', w') = M(phi)⁻¹ b.
  static Eigen::Vector2d accelerations(std::span<const double> x, double force,
                                       std::span<const double> p) {
    auto [mass, b] = mass_matrix_and_forces(x, force, p);
    return mass.inverse() * b;
  }

  /// ∂(v', w')/∂z for z = (x, phi, v, w, F, m1, d1, m2, d2, l), as ∂a = M⁻¹(∂b − ∂M·a).
  static Eigen::Matrix<double, 2, 10> acceleration_derivatives(std::span<const double> x,
                                                               double force,
                                                               std::span<const double> p) {
    const double phi = x[1], v = x[2], w = x[3];
    const double m2 = p[2], l = p[4], g = gravity;
    const double s = std::sin(phi), c = std::cos(phi);
    auto [mass, b] = mass_matrix_and_forces(x, force, p);
    const Eigen::Matrix2d inv = mass.inverse();
    const Eigen::Vector2d a = inv * b;
    (void)v;
    Eigen::Matrix<double, 2, 10> db = Eigen::Matrix<double, 2, 10>::Zero();
    std::array<Eigen::Matrix2d, 10> dm;
    for (auto& m : dm) m.setZero();
    // phi
    db(0, 1) = m2 * l * c * w * w / 2, db(1, 1) = -m2 * g * l * c / 2;
    dm[1] << 0, -m2 * l * s / 2, -m2 * l * s / 2, 0;
    // v, w, F
    db(0, 2) = -p[1];
    db(0, 3) = m2 * l * s * w, db(1, 3) = -p[3];
    db(0, 4) = 1.0;
    // m1
    dm[5] << 1, 0, 0, 0;
    // d1, d2
    db(0, 6) = -x[2];
    db(1, 8) = -w;
    // m2
    db(0, 7) = l * s * w * w / 2, db(1, 7) = -g * l * s / 2;
    dm[7] << 1, l * c / 2, l * c / 2, l * l / 3;
    // l
    db(0, 9) = m2 * s * w * w / 2, db(1, 9) = -m2 * g * s / 2;
    dm[9] << 0, m2 * c / 2, m2 * c / 2, 2 * m2 * l / 3;
    Eigen::Matrix<double, 2, 10> da;
    for (int k = 0; k < 10; ++k) da.col(k) = inv * (db.col(k) - dm[k] * a);
    return da;
  }

private:
  static std::pair<Eigen::Matrix2d, Eigen::Vector2d>
  mass_matrix_and_forces(std::span<const double> x, double force, std::span<const double> p) {
    const double phi = x[1], v = x[2], w = x[3];
    const double m1 = p[0], d1 = p[1], m2 = p[2], d2 = p[3], l = p[4], g = gravity;
    const double s = std::sin(phi), c = std::cos(phi);
    Eigen::Matrix2d mass;
    mass << m1 + m2, m2 * l * c / 2, m2 * l * c / 2, m2 * l * l / 3;
    Eigen::Vector2d b(m2 * l * s * w * w / 2 - d1 * v + force, -m2 * g * l * s / 2 - d2 * w);
    return {mass, b};
  }

  ModelInfo info_;
  Sparsity sp_[7];
  Sparsity hf_, hh_;
};

// ---------------------------------------------------------------------------

/// h' = v, v' = -g; h(0) = h0, v(0) = 0; when h < 0: reinit(v, -e·pre(v)).
/// p = (g, e, h0); output y = h; discrete variable: the number of bounces.
class BouncingBall final : public Model {
public:
  BouncingBall() {
    info_.name = "BouncingBall";
    info_.states = {state("h", "m", 1.0), state("v", "m/s")};
    info_.outputs = {{"height", "", "m"}};
    info_.parameters = {parameter("g", "m/s2", 9.81), parameter("e", "1", 0.8),
                        parameter("h0", "m", 1.0)};
    info_.discrete = {{"bounces", "number of bounces so far", ""}};
    info_.num_event_indicators = 1;
    using P = std::pair<int, int>;
    sp_[0] = Sparsity::from_triplets(2, 2, std::vector<P>{{0, 1}});
    sp_[1] = Sparsity::empty(2, 0);
    sp_[2] = Sparsity::from_triplets(2, 3, std::vector<P>{{1, 0}});
    sp_[3] = Sparsity::from_triplets(1, 2, std::vector<P>{{0, 0}});
    sp_[4] = Sparsity::empty(1, 0);
    sp_[5] = Sparsity::empty(1, 3);
    sp_[6] = Sparsity::from_triplets(2, 3, std::vector<P>{{0, 2}});
  }
  const ModelInfo& info() const override { return info_; }
  std::unique_ptr<Model> clone() const override { return std::make_unique<BouncingBall>(*this); }
  void initial_state(double, std::span<const double>, std::span<const double> p, std::span<double> x0) override {
    x0[0] = p[2];
    x0[1] = 0.0;
    bounces_ = pre_bounces_ = 0.0;
  }
  void rhs(double, std::span<const double> x, std::span<const double>,
           std::span<const double> p, std::span<double> xdot) override {
    xdot[0] = x[1];
    xdot[1] = -p[0];
  }
  void outputs(double, std::span<const double> x, std::span<const double>,
               std::span<const double>, std::span<double> y) override {
    y[0] = x[0];
  }
  const Sparsity& jacobian_sparsity(Jacobian block) const override {
    return sp_[static_cast<int>(block)];
  }
  void jacobian_values(Jacobian block, double, std::span<const double>, std::span<const double>,
                       std::span<const double>, std::span<double> v) override {
    switch (block) {
    case Jacobian::f_x: v[0] = 1.0; return;
    case Jacobian::f_p: v[0] = -1.0; return;
    case Jacobian::h_x: v[0] = 1.0; return;
    case Jacobian::x0_p: v[0] = 1.0; return;
    case Jacobian::f_u:
    case Jacobian::h_u:
    case Jacobian::h_p: return;
    }
  }
  void event_indicators(double, std::span<const double> x, std::span<const double>,
                        std::span<const double>, std::span<double> g) override {
    g[0] = x[0];
  }
  EventResponse handle_event(const EventCause& cause, std::span<double> x,
                             std::span<const double>, std::span<const double> p) override {
    pre_bounces_ = bounces_;
    // `h < 0` becomes true exactly when h crosses zero downwards.
    bool condition = !cause.crossings.empty() && cause.crossings[0] < 0;
    if (!condition) return {};
    x[1] = -p[1] * x[1];  // pre(v) is the left limit, still in x[1]
    bounces_ = pre_bounces_ + 1.0;
    return {.discrete_changed = bounces_ != pre_bounces_, .states_reinit = true};
  }
  std::span<double> discrete() override { return {&bounces_, 1}; }

private:
  ModelInfo info_;
  Sparsity sp_[7];
  double bounces_ = 0.0, pre_bounces_ = 0.0;
};

// ---------------------------------------------------------------------------

/// s' = v, v' = u; outputs y = (u², s, v); no parameters. The Lagrange integrand
/// u² makes ∫u² dt the energy of a rest-to-rest move; exact Hessians.
class DoubleIntegrator final : public Model {
public:
  DoubleIntegrator() {
    info_.name = "DoubleIntegrator";
    info_.states = {state("s", "m"), state("v", "m/s")};
    info_.inputs = {{"u", "acceleration", "m/s2"}};
    info_.outputs = {{"energy_rate", "u^2", "m2/s4"}, {"position", "", "m"}, {"speed", "", "m/s"}};
    using P = std::pair<int, int>;
    sp_[0] = Sparsity::from_triplets(2, 2, std::vector<P>{{0, 1}});  // f_x
    sp_[1] = Sparsity::from_triplets(2, 1, std::vector<P>{{1, 0}});  // f_u
    sp_[2] = Sparsity::empty(2, 0);
    sp_[3] = Sparsity::from_triplets(3, 2, std::vector<P>{{1, 0}, {2, 1}});  // h_x
    sp_[4] = Sparsity::from_triplets(3, 1, std::vector<P>{{0, 0}});          // h_u
    sp_[5] = Sparsity::empty(3, 0);
    sp_[6] = Sparsity::empty(2, 0);
    hf_ = Sparsity::empty(3, 3);
    hh_ = Sparsity::from_triplets(3, 3, std::vector<P>{{2, 2}});  // ∂²(μ0 u²)/∂u² = 2 μ0
  }
  const ModelInfo& info() const override { return info_; }
  std::unique_ptr<Model> clone() const override {
    return std::make_unique<DoubleIntegrator>(*this);
  }
  void initial_state(double, std::span<const double>, std::span<const double>, std::span<double> x0) override {
    x0[0] = x0[1] = 0.0;
  }
  void rhs(double, std::span<const double> x, std::span<const double> u,
           std::span<const double>, std::span<double> xdot) override {
    xdot[0] = x[1];
    xdot[1] = u[0];
  }
  void outputs(double, std::span<const double> x, std::span<const double> u,
               std::span<const double>, std::span<double> y) override {
    y[0] = u[0] * u[0], y[1] = x[0], y[2] = x[1];
  }
  const Sparsity& jacobian_sparsity(Jacobian block) const override {
    return sp_[static_cast<int>(block)];
  }
  void jacobian_values(Jacobian block, double, std::span<const double>,
                       std::span<const double> u, std::span<const double>,
                       std::span<double> v) override {
    switch (block) {
    case Jacobian::f_x:
    case Jacobian::f_u: v[0] = 1.0; return;
    case Jacobian::h_x: v[0] = 1.0, v[1] = 1.0; return;
    case Jacobian::h_u: v[0] = 2.0 * u[0]; return;
    case Jacobian::f_p:
    case Jacobian::h_p:
    case Jacobian::x0_p: return;
    }
  }
  bool provides_hessian(Hessian) const override { return true; }
  const Sparsity& hessian_sparsity(Hessian which) const override {
    return which == Hessian::f ? hf_ : hh_;
  }
  void hessian_values(Hessian which, double, std::span<const double>, std::span<const double>,
                      std::span<const double>, std::span<const double> w,
                      std::span<double> v) override {
    if (which == Hessian::h) v[0] = 2.0 * w[0];
  }

private:
  ModelInfo info_;
  Sparsity sp_[7];
  Sparsity hf_, hh_;
};

// ---------------------------------------------------------------------------

/// `Base` plus its forward sensitivities for every parameter as states, the
/// way the compiler appends them: S(i, j) = ∂x_i/∂p_j at index nx + i·np + j,
/// named d(x_i)/d(p_j), with der(S) = f_x S + f_p and S(0) = ∂x0/∂p — using
/// Base's Jacobians. The augmented Jacobian's ∂(f_x S + f_p)/∂(x, u, p) terms
/// are central differences of Base's Jacobians (fixture only); outputs are Base's.
template <class Base>
class WithSensitivities final : public Model {
public:
  WithSensitivities() {
    const ModelInfo& b = base_.info();
    nx_ = b.states.size(), nu_ = b.inputs.size(), np_ = b.parameters.size(),
    ny_ = b.outputs.size();
    info_ = b;
    info_.name = b.name + "WithSensitivities";
    for (std::size_t i = 0; i < nx_; ++i)
      for (std::size_t j = 0; j < np_; ++j) {
        StateVariable s;
        s.name = "d(" + b.states[i].name + ")/d(" + b.parameters[j].name + ")";
        s.sensitivity = SensitivityOf{i, j};
        info_.states.push_back(s);
      }
    int n = static_cast<int>(nx_ * (1 + np_));
    int nu = static_cast<int>(nu_), np = static_cast<int>(np_), ny = static_cast<int>(ny_);
    sp_[0] = Sparsity::dense(n, n);
    sp_[1] = Sparsity::dense(n, nu);
    sp_[2] = Sparsity::dense(n, np);
    sp_[3] = Sparsity::dense(ny, n);
    sp_[4] = Sparsity::dense(ny, nu);
    sp_[5] = Sparsity::dense(ny, np);
    sp_[6] = Sparsity::dense(n, np);
  }
  const ModelInfo& info() const override { return info_; }
  std::unique_ptr<Model> clone() const override {
    return std::make_unique<WithSensitivities>(*this);
  }
  void initial_state(double t0, std::span<const double> u0, std::span<const double> p, std::span<double> x0) override {
    base_.initial_state(t0, u0, p, x0.subspan(0, nx_));
    Eigen::MatrixXd s0 = dense(Jacobian::x0_p, 0.0, x0.subspan(0, nx_), {}, p);
    for (std::size_t i = 0; i < nx_; ++i)
      for (std::size_t j = 0; j < np_; ++j) x0[nx_ + i * np_ + j] = s0(i, j);
  }
  void rhs(double t, std::span<const double> x, std::span<const double> u,
           std::span<const double> p, std::span<double> xdot) override {
    base_.rhs(t, x.subspan(0, nx_), u, p, xdot.subspan(0, nx_));
    Eigen::MatrixXd sdot = sensitivity_rhs(t, x, u, p);
    for (std::size_t i = 0; i < nx_; ++i)
      for (std::size_t j = 0; j < np_; ++j) xdot[nx_ + i * np_ + j] = sdot(i, j);
  }
  void outputs(double t, std::span<const double> x, std::span<const double> u,
               std::span<const double> p, std::span<double> y) override {
    base_.outputs(t, x.subspan(0, nx_), u, p, y);
  }
  const Sparsity& jacobian_sparsity(Jacobian block) const override {
    return sp_[static_cast<int>(block)];
  }
  void jacobian_values(Jacobian block, double t, std::span<const double> x,
                       std::span<const double> u, std::span<const double> p,
                       std::span<double> v) override {
    const auto n = static_cast<Eigen::Index>(nx_ * (1 + np_));
    auto xb = x.subspan(0, std::min(x.size(), nx_));
    switch (block) {
    case Jacobian::f_x: {
      Eigen::MatrixXd j = Eigen::MatrixXd::Zero(n, n);
      Eigen::MatrixXd fx = dense(Jacobian::f_x, t, xb, u, p);
      j.topLeftCorner(nx_, nx_) = fx;
      for (std::size_t i = 0; i < nx_; ++i)  // ∂Sdot/∂S: f_x acting on each column j
        for (std::size_t k = 0; k < nx_; ++k)
          for (std::size_t pj = 0; pj < np_; ++pj)
            j(nx_ + i * np_ + pj, nx_ + k * np_ + pj) = fx(i, k);
      std::vector<double> xs(x.begin(), x.end());
      for (std::size_t k = 0; k < nx_; ++k)  // ∂Sdot/∂x_k by central differences
        j.block(nx_, k, nx_ * np_, 1) = difference(xs, k, [&](std::span<const double> xk) {
          return flatten(sensitivity_rhs(t, xk, u, p));
        });
      copy_dense(j, v);
      return;
    }
    case Jacobian::f_u:
    case Jacobian::f_p: {
      bool wrt_u = block == Jacobian::f_u;
      std::size_t m = wrt_u ? nu_ : np_;
      Eigen::MatrixXd j = Eigen::MatrixXd::Zero(n, m);
      j.topRows(nx_) = dense(block, t, xb, u, p);
      std::vector<double> arg(wrt_u ? u.begin() : p.begin(), wrt_u ? u.end() : p.end());
      for (std::size_t k = 0; k < m; ++k)
        j.block(nx_, k, nx_ * np_, 1) = difference(arg, k, [&](std::span<const double> a) {
          return flatten(wrt_u ? sensitivity_rhs(t, x, a, p) : sensitivity_rhs(t, x, u, a));
        });
      copy_dense(j, v);
      return;
    }
    case Jacobian::h_x: {
      Eigen::MatrixXd j = Eigen::MatrixXd::Zero(ny_, n);
      j.leftCols(nx_) = dense(Jacobian::h_x, t, xb, u, p);
      copy_dense(j, v);
      return;
    }
    case Jacobian::h_u:
    case Jacobian::h_p: copy_dense(dense(block, t, xb, u, p), v); return;
    case Jacobian::x0_p: {
      // S(0) = ∂x0/∂p depends on p only through Base's ∂x0/∂p, constant for our fixtures.
      Eigen::MatrixXd j = Eigen::MatrixXd::Zero(n, np_);
      j.topRows(nx_) = dense(Jacobian::x0_p, t, xb, u, p);
      copy_dense(j, v);
      return;
    }
    }
  }

  /// Base's Jacobian block as a dense matrix.
  Eigen::MatrixXd dense(Jacobian block, double t, std::span<const double> x,
                        std::span<const double> u, std::span<const double> p) {
    const Sparsity& sp = base_.jacobian_sparsity(block);
    std::vector<double> values(static_cast<std::size_t>(sp.nnz()));
    std::vector<double> xs(x.begin(), x.end());
    xs.resize(nx_);
    std::vector<double> us(u.begin(), u.end());
    us.resize(nu_);
    base_.jacobian_values(block, t, xs, us, p, values);
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(sp.rows, sp.cols);
    for (int c = 0; c < sp.cols; ++c)
      for (int k = sp.col_start[c]; k < sp.col_start[c + 1]; ++k) m(sp.row_index[k], c) = values[k];
    return m;
  }

private:
  // f_x S + f_p with S read from x's tail (nx × np).
  Eigen::MatrixXd sensitivity_rhs(double t, std::span<const double> x, std::span<const double> u,
                                  std::span<const double> p) {
    Eigen::MatrixXd s(nx_, np_);
    for (std::size_t i = 0; i < nx_; ++i)
      for (std::size_t j = 0; j < np_; ++j) s(i, j) = x[nx_ + i * np_ + j];
    auto xb = x.subspan(0, nx_);
    return dense(Jacobian::f_x, t, xb, u, p) * s + dense(Jacobian::f_p, t, xb, u, p);
  }
  Eigen::VectorXd flatten(const Eigen::MatrixXd& s) const {  // row-major, as stored in x
    Eigen::VectorXd out(s.size());
    for (Eigen::Index i = 0; i < s.rows(); ++i)
      for (Eigen::Index j = 0; j < s.cols(); ++j) out[i * s.cols() + j] = s(i, j);
    return out;
  }
  template <class F>
  Eigen::VectorXd difference(std::vector<double> arg, std::size_t k, F&& f) {
    double step = 1e-6 * std::max(1.0, std::abs(arg[k]));
    double centre = arg[k];
    arg[k] = centre + step;
    Eigen::VectorXd plus = f(arg);
    arg[k] = centre - step;
    Eigen::VectorXd minus = f(arg);
    return (plus - minus) / (2.0 * step);
  }

  Base base_;
  ModelInfo info_;
  std::size_t nx_ = 0, nu_ = 0, np_ = 0, ny_ = 0;
  Sparsity sp_[7];
};

}  // namespace mo::runtime::fixtures
