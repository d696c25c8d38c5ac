// Forward sensitivities four ways on the cart-pendulum: CVODES with the
// model's Jacobians, CVODES' difference quotients, the sensitivity-augmented
// fixture (sensitivities as states), and central differences of simulations.
// They must agree to 1e-5 relative; the linear ODE's against its analytic ones.
#include "fixtures.hpp"
#include "mo/runtime/simulate.hpp"

#include <catch2/catch.hpp>

using namespace mo::runtime;
using namespace mo::runtime::fixtures;

namespace {

SimulationOptions tight(SensitivityMethod method, std::vector<std::size_t> parameters) {
  SimulationOptions o;
  o.relative_tolerance = 1e-10;
  o.absolute_tolerance = 1e-12;
  o.sensitivities.method = method;
  o.sensitivities.parameters = std::move(parameters);
  return o;
}

std::function<Inputs()> sine_force = [] {
  Inputs inputs;
  inputs.add(sine_input(3.0, 1.0));
  return inputs;
};

// S_x(t_k) by central differences of simulations, one matrix per output time.
std::vector<Eigen::MatrixXd> finite_difference_sensitivities(
    Model& model, const std::function<Inputs()>& make_inputs, std::vector<double> p,
    const OutputGrid& grid, const std::vector<std::size_t>& parameters) {
  const std::size_t nx = model.info().states.size();
  std::vector<Eigen::MatrixXd> s(grid.times.size(),
                                 Eigen::MatrixXd(nx, static_cast<Eigen::Index>(parameters.size())));
  auto options = tight(SensitivityMethod::none, {});
  options.relative_tolerance = 1e-12;
  options.absolute_tolerance = 1e-14;
  for (std::size_t j = 0; j < parameters.size(); ++j) {
    std::size_t pj = parameters[j];
    double centre = p[pj], step = 1e-4 * std::max(1.0, std::abs(centre));
    p[pj] = centre + step;
    auto plus = simulate(model, make_inputs(), p, grid, options);
    p[pj] = centre - step;
    auto minus = simulate(model, make_inputs(), p, grid, options);
    p[pj] = centre;
    REQUIRE(plus.ok());
    REQUIRE(minus.ok());
    for (std::size_t k = 0; k < grid.times.size(); ++k)
      for (std::size_t i = 0; i < nx; ++i)
        s[k](static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
            (plus.trajectory.at(k, i) - minus.trajectory.at(k, i)) / (2 * step);
  }
  return s;
}

// max over k, i, j of |a - b| / scale(i, j), scale = max_k |b(i, j)| (floored).
double relative_difference(const std::vector<Eigen::MatrixXd>& a,
                           const std::vector<Eigen::MatrixXd>& b) {
  REQUIRE(a.size() == b.size());
  REQUIRE(!b.empty());
  Eigen::MatrixXd scale = Eigen::MatrixXd::Constant(b[0].rows(), b[0].cols(), 1e-12);
  for (const auto& m : b) scale = scale.cwiseMax(m.cwiseAbs());
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    REQUIRE(a[k].rows() == b[k].rows());
    REQUIRE(a[k].cols() == b[k].cols());
    worst = std::max(worst, ((a[k] - b[k]).cwiseAbs().array() / scale.array()).maxCoeff());
  }
  return worst;
}

}  // namespace

TEST_CASE("Cart-pendulum sensitivities for p = (m1, d1, m2, d2, l) agree four ways",
          "[sensitivities]") {
  CartPendulum model;
  const auto p = model.info().default_parameters();
  const std::vector<std::size_t> all{0, 1, 2, 3, 4};
  const auto grid = OutputGrid::uniform(0, 10, 50);

  auto analytic = simulate(model, sine_force(), p, grid,
                           tight(SensitivityMethod::cvodes_analytic, all));
  REQUIRE(analytic.status == SimulationStatus::success);
  REQUIRE(analytic.state_sensitivities.size() == grid.times.size());
  CHECK(analytic.sensitivity_parameters == all);
  CHECK(analytic.statistics.sensitivity_rhs_evaluations > 0);

  // Difference quotients carry ~sqrt(eps) noise: with sensitivity error control
  // CVODES cannot meet rtol 1e-10 with them (too_much_work), so they get 1e-8.
  auto dq_options = tight(SensitivityMethod::cvodes_difference, all);
  dq_options.relative_tolerance = 1e-8;
  dq_options.absolute_tolerance = 1e-10;
  auto difference = simulate(model, sine_force(), p, grid, dq_options);
  REQUIRE(difference.status == SimulationStatus::success);

  WithSensitivities<CartPendulum> augmented;
  auto as_states = simulate(augmented, sine_force(), p, grid,
                            tight(SensitivityMethod::model_states, {}));
  REQUIRE(as_states.status == SimulationStatus::success);
  CHECK(as_states.sensitivity_parameters == all);

  auto fd = finite_difference_sensitivities(model, sine_force, p, grid, all);

  CHECK(relative_difference(analytic.state_sensitivities, fd) < 1e-5);
  CHECK(relative_difference(difference.state_sensitivities, fd) < 1e-5);
  CHECK(relative_difference(as_states.state_sensitivities, fd) < 1e-5);
  CHECK(relative_difference(analytic.state_sensitivities, as_states.state_sensitivities) < 1e-5);

  // Output sensitivities S_y = ∂h/∂x S_x: y = (x, phi) picks rows 0 and 1.
  const auto& sy = analytic.output_sensitivities.back();
  const auto& sx = analytic.state_sensitivities.back();
  CHECK(sy.row(0) == sx.row(0));
  CHECK(sy.row(1) == sx.row(1));
  CHECK(as_states.output_sensitivities.back().isApprox(sy, 1e-5));

  // ∂phi/∂m2 is the quantity the experiment design maximises: not trivially zero.
  double largest = 0.0;
  for (const auto& s : analytic.state_sensitivities) largest = std::max(largest, std::abs(s(1, 2)));
  CHECK(largest > 1e-3);
}

TEST_CASE("Sensitivities stay right across input breakpoints (restarts)", "[sensitivities]") {
  CartPendulum model;
  const auto p = model.info().default_parameters();
  std::function<Inputs()> steps = [] {
    Inputs inputs;
    inputs.add(piecewise_constant_input({0.0, 0.7, 1.3, 2.1}, {2.0, -3.0, 4.0, 0.0}));
    return inputs;
  };
  const auto grid = OutputGrid::uniform(0, 3, 30);
  const std::vector<std::size_t> some{2, 4};
  auto analytic = simulate(model, steps(), p, grid, tight(SensitivityMethod::cvodes_analytic, some));
  REQUIRE(analytic.ok());
  CHECK(analytic.statistics.restarts == 3);
  auto fd = finite_difference_sensitivities(model, steps, p, grid, some);
  CHECK(relative_difference(analytic.state_sensitivities, fd) < 1e-5);
}

TEST_CASE("Linear ODE sensitivities, including S(0) = ∂x0/∂p, match the analytic ones",
          "[sensitivities]") {
  LinearDecay model;
  const double k = 2.0, a0 = 1.5, u = 0.5;
  std::vector<double> p{k, a0};
  for (auto method : {SensitivityMethod::cvodes_analytic, SensitivityMethod::cvodes_difference}) {
    Inputs inputs;
    inputs.add(constant_input(u));
    auto result = simulate(model, inputs, p, OutputGrid::uniform(0, 2, 20),
                           tight(method, {0, 1}));
    REQUIRE(result.ok());
    for (std::size_t r = 0; r < result.trajectory.rows(); ++r) {
      double t = result.trajectory.times()[r], e = std::exp(-k * t), c = a0 - u / k;
      double b = u * t / k + c * (1 - e) / k;
      double da_dk = -u / (k * k) + u / (k * k) * e - c * t * e;
      double db_dk = -u * t / (k * k) + (u / (k * k)) * (1 - e) / k +
                     c * (t * e / k - (1 - e) / (k * k));
      const auto& s = result.state_sensitivities[r];
      CHECK(s(0, 0) == Approx(da_dk).margin(1e-7));
      CHECK(s(0, 1) == Approx(e).margin(1e-7));
      CHECK(s(1, 0) == Approx(db_dk).margin(1e-7));
      CHECK(s(1, 1) == Approx((1 - e) / k).margin(1e-7));
      // y1 = k b: ∂y1/∂k = b + k ∂b/∂k — exercises ∂h/∂p.
      CHECK(result.output_sensitivities[r](1, 0) == Approx(b + k * db_dk).margin(1e-7));
    }
  }
}
