// The fixtures' hand-written Jacobians and Hessians against finite differences,
// and the Sparsity helpers every generated model relies on.
#include "fixtures.hpp"

#include <catch2/catch.hpp>

#include <functional>

using namespace mo::runtime;
using namespace mo::runtime::fixtures;

namespace {

// A model point (t, x, u, p) at which derivatives are compared.
struct Point {
  double t;
  std::vector<double> x, u, p;
};

Eigen::MatrixXd to_dense(const Sparsity& sp, const std::vector<double>& values) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(sp.rows, sp.cols);
  for (int c = 0; c < sp.cols; ++c)
    for (int k = sp.col_start[c]; k < sp.col_start[c + 1]; ++k) m(sp.row_index[k], c) = values[k];
  return m;
}

// Central differences of a vector function of one argument vector.
Eigen::MatrixXd central_difference(std::vector<double> arg, std::size_t rows,
                                   const std::function<void(std::span<const double>,
                                                            std::span<double>)>& f) {
  Eigen::MatrixXd j(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(arg.size()));
  std::vector<double> plus(rows), minus(rows);
  for (std::size_t k = 0; k < arg.size(); ++k) {
    double centre = arg[k], step = 1e-6 * std::max(1.0, std::abs(centre));
    arg[k] = centre + step;
    f(arg, plus);
    arg[k] = centre - step;
    f(arg, minus);
    arg[k] = centre;
    for (std::size_t r = 0; r < rows; ++r)
      j(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(k)) = (plus[r] - minus[r]) / (2 * step);
  }
  return j;
}

// Every Jacobian block of `model` at `pt` equals central differences of rhs,
// outputs and initial_state (relative to the block's largest entry), and the
// pattern has the right shape and covers every nonzero.
void check_jacobians(Model& model, const Point& pt, double tolerance) {
  const ModelInfo& info = model.info();
  const std::size_t nx = info.states.size(), ny = info.outputs.size();
  auto f_of = [&](int which) {  // 0: f, 1: h
    return [&, which](const std::vector<double>& x, const std::vector<double>& u,
                      const std::vector<double>& p, std::span<double> out) {
      if (which == 0) model.rhs(pt.t, x, u, p, out);
      else model.outputs(pt.t, x, u, p, out);
    };
  };
  struct Case {
    Jacobian block;
    int function;  // 0 f, 1 h, 2 x0
    int argument;  // 0 x, 1 u, 2 p
  };
  const Case cases[] = {{Jacobian::f_x, 0, 0}, {Jacobian::f_u, 0, 1}, {Jacobian::f_p, 0, 2},
                        {Jacobian::h_x, 1, 0}, {Jacobian::h_u, 1, 1}, {Jacobian::h_p, 1, 2},
                        {Jacobian::x0_p, 2, 2}};
  for (const Case& c : cases) {
    INFO("model " << info.name << ", block " << static_cast<int>(c.block));
    const Sparsity& sp = model.jacobian_sparsity(c.block);
    REQUIRE(sp.is_valid());
    std::size_t rows = c.function == 1 ? ny : nx;
    const std::vector<double>& arg = c.argument == 0 ? pt.x : c.argument == 1 ? pt.u : pt.p;
    REQUIRE(sp.rows == static_cast<int>(rows));
    REQUIRE(sp.cols == static_cast<int>(arg.size()));
    std::vector<double> values(static_cast<std::size_t>(sp.nnz()));
    model.jacobian_values(c.block, pt.t, pt.x, pt.u, pt.p, values);
    Eigen::MatrixXd exact = to_dense(sp, values);
    Eigen::MatrixXd fd = central_difference(arg, rows, [&](std::span<const double> a,
                                                          std::span<double> out) {
      std::vector<double> x = pt.x, u = pt.u, p = pt.p;
      std::vector<double> av(a.begin(), a.end());
      (c.argument == 0 ? x : c.argument == 1 ? u : p) = av;
      if (c.function == 2) model.initial_state(p, out);
      else f_of(c.function)(x, u, p, out);
    });
    if (fd.size() == 0) continue;  // e.g. ∂f/∂u of a model without inputs
    double scale = std::max(1.0, fd.cwiseAbs().maxCoeff());
    CHECK((exact - fd).cwiseAbs().maxCoeff() <= tolerance * scale);
  }
}

}  // namespace

TEST_CASE("Sparsity: CSC built from triplets, looked up, validated", "[model]") {
  using P = std::pair<int, int>;
  std::vector<P> entries{{2, 1}, {0, 0}, {1, 1}, {2, 1}};
  Sparsity s = Sparsity::from_triplets(3, 2, entries);
  CHECK(s.is_valid());
  CHECK(s.nnz() == 3);
  CHECK(s.col_start == std::vector<int>{0, 1, 3});
  CHECK(s.row_index == std::vector<int>{0, 1, 2});
  CHECK(s.find(2, 1) == 2);
  CHECK(s.find(1, 0) == -1);
  CHECK(Sparsity::dense(2, 3).nnz() == 6);
  CHECK(Sparsity::dense(2, 3).is_valid());
  CHECK(Sparsity::empty(4, 0).is_valid());
  std::vector<P> outside{{3, 0}};
  CHECK_THROWS_AS(Sparsity::from_triplets(3, 2, outside), std::invalid_argument);
  Sparsity broken = s;
  broken.row_index = {0, 2, 1};  // rows must ascend within a column
  CHECK_FALSE(broken.is_valid());
}

TEST_CASE("ModelInfo look-ups and sensitivity metadata", "[model]") {
  WithSensitivities<CartPendulum> model;
  const ModelInfo& info = model.info();
  CHECK(info.states.size() == 24);
  CHECK(info.num_base_states() == 4);
  auto k = info.state_index("d(phi)/d(m2)");
  REQUIRE(k);
  REQUIRE(info.states[*k].sensitivity);
  CHECK(info.states[*k].sensitivity->state == 1);
  CHECK(info.states[*k].sensitivity->parameter == 2);
  CHECK(info.parameter_index("l") == 4u);
  CHECK_FALSE(info.output_index("nope"));
  CHECK(info.default_parameters() == std::vector<double>{2.0, 15.0, 1.0, 0.5, 0.5});
}

TEST_CASE("Cart-pendulum hand Jacobians match finite differences", "[model]") {
  CartPendulum model;
  // Away from rest, so that every trigonometric term matters.
  check_jacobians(model, {0.3, {0.1, 0.7, -0.4, 1.3}, {2.5}, {2.0, 15.0, 1.0, 0.5, 0.5}}, 1e-7);
  check_jacobians(model, {0.0, {0.0, -2.0, 0.2, -0.8}, {-5.0}, {1.5, 10.0, 0.7, 0.3, 0.9}}, 1e-7);
}

TEST_CASE("Linear and bouncing-ball Jacobians match finite differences", "[model]") {
  LinearDecay linear;
  check_jacobians(linear, {0.5, {0.3, -1.2}, {0.7}, {2.0, 1.5}}, 1e-8);
  BouncingBall ball;
  check_jacobians(ball, {0.1, {0.5, -1.0}, {}, {9.81, 0.8, 1.0}}, 1e-8);
}

TEST_CASE("Sensitivity-augmented cart-pendulum Jacobians match finite differences", "[model]") {
  WithSensitivities<CartPendulum> model;
  Point pt{0.2, std::vector<double>(24), {1.0}, {2.0, 15.0, 1.0, 0.5, 0.5}};
  pt.x[1] = 0.4, pt.x[2] = 0.3, pt.x[3] = -0.6;
  for (std::size_t k = 4; k < 24; ++k) pt.x[k] = 0.1 * std::sin(double(k));
  check_jacobians(model, pt, 1e-6);  // its f_x is itself a difference of hand Jacobians
}

TEST_CASE("Hessians of the contractions: lower triangle, matches second differences", "[model]") {
  SECTION("cart-pendulum: λᵀf against second differences of rhs") {
    CartPendulum model;
    REQUIRE(model.provides_hessian(Hessian::f));
    std::vector<double> z{0.1, 0.7, -0.4, 1.3, 2.5, 2.0, 15.0, 1.0, 0.5, 0.5};
    std::vector<double> lambda{0.3, -0.2, 1.1, 0.7};
    const Sparsity& sp = model.hessian_sparsity(Hessian::f);
    REQUIRE(sp.is_valid());
    REQUIRE(sp.rows == 10);
    for (int c = 0; c < sp.cols; ++c)
      for (int k = sp.col_start[c]; k < sp.col_start[c + 1]; ++k) REQUIRE(sp.row_index[k] >= c);
    std::span<const double> zs(z);
    std::vector<double> values(static_cast<std::size_t>(sp.nnz()));
    model.hessian_values(Hessian::f, 0.0, zs.subspan(0, 4), zs.subspan(4, 1), zs.subspan(5, 5),
                         lambda, values);
    auto contraction = [&](std::vector<double> a) {
      std::vector<double> f(4);
      std::span<const double> as(a);
      model.rhs(0.0, as.subspan(0, 4), as.subspan(4, 1), as.subspan(5, 5), f);
      return lambda[0] * f[0] + lambda[1] * f[1] + lambda[2] * f[2] + lambda[3] * f[3];
    };
    Eigen::MatrixXd exact = to_dense(sp, values);
    for (int r = 0; r < 10; ++r)
      for (int c = 0; c <= r; ++c) {
        double hr = 1e-4 * std::max(1.0, std::abs(z[r])), hc = 1e-4 * std::max(1.0, std::abs(z[c]));
        auto at = [&](double dr, double dc) {
          auto a = z;
          a[r] += dr;
          a[c] += dc;
          return contraction(a);
        };
        double fd = (at(hr, hc) - at(hr, -hc) - at(-hr, hc) + at(-hr, -hc)) / (4 * hr * hc);
        INFO("entry (" << r << ", " << c << ")");
        CHECK(exact(r, c) == Approx(fd).margin(1e-5).epsilon(1e-5));
      }
  }
  SECTION("linear model: exact Hessians of f and h") {
    LinearDecay model;
    std::vector<double> x{0.3, 0.4}, u{1.0}, p{2.0, 1.0}, lambda{0.5, 2.0}, mu{3.0, -1.0}, v(1);
    model.hessian_values(Hessian::f, 0.0, x, u, p, lambda, v);
    CHECK(v[0] == -0.5);  // ∂²(λ0·(−k a))/∂k∂a
    CHECK(model.hessian_sparsity(Hessian::f).find(3, 0) == 0);
    model.hessian_values(Hessian::h, 0.0, x, u, p, mu, v);
    CHECK(v[0] == -1.0);  // ∂²(μ1·k b)/∂k∂b
  }
  SECTION("a model without Hessians says so") {
    BouncingBall model;
    CHECK_FALSE(model.provides_hessian(Hessian::f));
    CHECK_THROWS_AS(model.hessian_sparsity(Hessian::f), std::logic_error);
  }
}
