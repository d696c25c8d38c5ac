// Forward sensitivities of the cart-pendulum .mo for all five parameters
// (m1, d1, m2, d2, l), three independent ways: the sensitivity equations the
// compiler generated (model states), CVODES' sensitivity module on the plain
// model's Jacobians, and central differences of simulations.
#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

const std::vector<std::string> kParameters{"m1", "d1", "m2", "d2", "l"};

runtime::Inputs sine_force() {
  runtime::Inputs inputs;
  inputs.add(runtime::sine_input(3.0, 1.0));
  return inputs;
}

runtime::SimulationOptions tight(runtime::SensitivityMethod method, std::vector<std::size_t> parameters) {
  runtime::SimulationOptions o;
  o.relative_tolerance = 1e-10;
  o.absolute_tolerance = 1e-12;
  o.sensitivities.method = method;
  o.sensitivities.parameters = std::move(parameters);
  return o;
}

/// max over k, i, j of |a - b| / max_k |b(i, j)| (scale floored at 1e-12).
double relative_difference(const std::vector<Eigen::MatrixXd>& a, const std::vector<Eigen::MatrixXd>& b) {
  REQUIRE(a.size() == b.size());
  REQUIRE(a.front().rows() == b.front().rows());
  REQUIRE(a.front().cols() == b.front().cols());
  Eigen::MatrixXd scale = Eigen::MatrixXd::Constant(b.front().rows(), b.front().cols(), 1e-12);
  for (const auto& m : b) scale = scale.cwiseMax(m.cwiseAbs());
  double worst = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
    worst = std::max(worst, ((a[k] - b[k]).cwiseAbs().array() / scale.array()).maxCoeff());
  return worst;
}

}  // namespace

TEST_CASE("cart-pendulum sensitivities to m1 d1 m2 d2 l: generated equations = CVODES = finite differences") {
  const tools::ModelSource source{kModelica + "CartPendulum/CartPendulumODE.mo", "CartPendulumODE", {}, true};
  auto plain = compiled_model("e2e_cart_pendulum_ode", {source, {}});
  auto augmented = compiled_model("e2e_cart_pendulum_ode_sens", {source, kParameters});
  const auto& info = plain->info();
  REQUIRE(augmented->info().num_base_states() == 4);
  std::vector<std::size_t> J, J_augmented;
  for (const auto& name : kParameters) {
    J.push_back(parameter(info, name));
    J_augmented.push_back(parameter(augmented->info(), name));
  }
  const auto grid = runtime::OutputGrid::uniform(0, 10, 100);
  const auto p = info.default_parameters();

  const auto generated = runtime::simulate(*augmented, sine_force(), augmented->info().default_parameters(), grid,
                                           tight(runtime::SensitivityMethod::model_states, J_augmented));
  INFO(generated.message);
  REQUIRE(generated.ok());
  const auto cvodes =
      runtime::simulate(*plain, sine_force(), p, grid, tight(runtime::SensitivityMethod::cvodes_analytic, J));
  INFO(cvodes.message);
  REQUIRE(cvodes.ok());
  REQUIRE(generated.state_sensitivities.size() == grid.times.size());
  REQUIRE(cvodes.state_sensitivities.size() == grid.times.size());
  REQUIRE(generated.state_sensitivities.front().rows() == 4);
  REQUIRE(generated.state_sensitivities.front().cols() == 5);

  // The base trajectories of both models agree.
  for (const char* s : {"x", "phi", "v", "w"})
    CHECK(max_abs_difference(column(generated.trajectory, s), column(cvodes.trajectory, s)) < 1e-8);

  // Central differences of simulations at rtol 1e-12, step 1e-4·max(1, |p|).
  std::vector<Eigen::MatrixXd> fd(grid.times.size(), Eigen::MatrixXd(4, 5));
  auto reference = tight(runtime::SensitivityMethod::none, {});
  reference.relative_tolerance = 1e-12;
  reference.absolute_tolerance = 1e-14;
  for (std::size_t j = 0; j < J.size(); ++j) {
    auto q = p;
    const double step = 1e-4 * std::max(1.0, std::fabs(p[J[j]]));
    q[J[j]] = p[J[j]] + step;
    const auto plus = runtime::simulate(*plain, sine_force(), q, grid, reference);
    q[J[j]] = p[J[j]] - step;
    const auto minus = runtime::simulate(*plain, sine_force(), q, grid, reference);
    REQUIRE(plus.ok());
    REQUIRE(minus.ok());
    for (std::size_t k = 0; k < grid.times.size(); ++k)
      for (Eigen::Index i = 0; i < 4; ++i)
        fd[k](i, static_cast<Eigen::Index>(j)) =
            (plus.trajectory.at(k, static_cast<std::size_t>(i)) - minus.trajectory.at(k, static_cast<std::size_t>(i))) /
            (2 * step);
  }
  // CVODES' rows are the plain model's states, the generated ones the base states: same order?
  for (std::size_t i = 0; i < 4; ++i) REQUIRE(info.states[i].name == augmented->info().states[i].name);
  std::vector<Eigen::MatrixXd> cv(cvodes.state_sensitivities.begin(), cvodes.state_sensitivities.end());

  const double gen_vs_cvodes = relative_difference(generated.state_sensitivities, cv);
  const double gen_vs_fd = relative_difference(generated.state_sensitivities, fd);
  const double cvodes_vs_fd = relative_difference(cv, fd);
  WARN("cart-pendulum sensitivities, max relative difference: generated vs CVODES "
       << gen_vs_cvodes << ", generated vs FD " << gen_vs_fd << ", CVODES vs FD " << cvodes_vs_fd);
  CHECK(gen_vs_cvodes < 1e-5);
  CHECK(gen_vs_fd < 1e-5);
  CHECK(cvodes_vs_fd < 1e-5);

  // Output sensitivities dy/dp from the generated model equal S_x rows x, phi.
  const auto yx = augmented->info().output_index("y_x"), yphi = augmented->info().output_index("y_phi");
  REQUIRE(yx);
  REQUIRE(yphi);
  REQUIRE(generated.output_sensitivities.size() == grid.times.size());
  double worst_y = 0;
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    worst_y = std::max(worst_y, (generated.output_sensitivities[k].row(static_cast<Eigen::Index>(*yx)) -
                                 generated.state_sensitivities[k].row(0))
                                    .cwiseAbs()
                                    .maxCoeff());
    worst_y = std::max(worst_y, (generated.output_sensitivities[k].row(static_cast<Eigen::Index>(*yphi)) -
                                 generated.state_sensitivities[k].row(1))
                                    .cwiseAbs()
                                    .maxCoeff());
  }
  CHECK(worst_y < 1e-12);
  // Not all zero: m2 moves the pendulum.
  CHECK(std::fabs(fd.back()(1, 2)) + std::fabs(fd[50](1, 2)) > 1e-4);
}
