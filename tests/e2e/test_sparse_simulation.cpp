// Simulations of large sparse models on KLU (runtime/src/cvode_jacobian.hpp)
// against exact solutions, and against the same simulations on dense LU: a
// chain of 150 lags (the Erlang CDF and its derivative in the time constant)
// and a Jacobian taken by differences where the model's is not finite.
#include <cmath>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

/// P(k, λ) = 1 − e^{−λ} Σ_{j<k} λ^j/j! and its density e^{−λ} λ^{k−1}/(k−1)!.
std::pair<double, double> erlang(int k, double lambda) {
  double term = std::exp(-lambda), sum = 0.0;
  for (int j = 0; j < k - 1; ++j) sum += term, term *= lambda / (j + 1);
  return {1.0 - (sum + term), term};
}

std::unique_ptr<runtime::Model> lag_chain() {
  return compiled_model("e2e_lag_chain", {{kData + "LagChain.mo", "", {}, false}, {}});
}

runtime::SimulationOptions with(runtime::LinearSolverChoice choice, bool tau_sensitivity) {
  auto o = tight();
  o.linear_solver = choice;
  if (tau_sensitivity) {
    o.sensitivities.method = runtime::SensitivityMethod::cvodes_analytic;
    o.sensitivities.parameters = {0};  // set from the model below
  }
  return o;
}

}  // namespace

TEST_CASE("a chain of 150 lags simulates on KLU to its exact solution and as on dense LU", "[sparse]") {
  auto model = lag_chain();
  const auto& info = model->info();
  REQUIRE(info.states.size() == 150);
  std::size_t tau = 0;
  while (info.parameters[tau].name != "tau") ++tau;
  const auto grid = runtime::OutputGrid::uniform(0, 20, 40);
  std::map<runtime::LinearSolverChoice, runtime::SimulationResult> runs;
  for (auto choice : {runtime::LinearSolverChoice::automatic, runtime::LinearSolverChoice::dense}) {
    auto options = with(choice, true);
    options.sensitivities.parameters = {tau};
    runs[choice] = runtime::simulate(*model, {}, info.default_parameters(), grid, options);
    INFO(runs[choice].message);
    REQUIRE(runs[choice].ok());
  }
  const auto& sparse = runs[runtime::LinearSolverChoice::automatic];
  const auto& dense = runs[runtime::LinearSolverChoice::dense];
  CHECK(sparse.statistics.sparse_linear_solver);
  CHECK_FALSE(dense.statistics.sparse_linear_solver);
  for (int k : {1, 10, 100, 150}) {
    CAPTURE(k);
    const std::string name = "x[" + std::to_string(k) + "]";
    std::size_t state = 0;
    while (info.states[state].name != name) ++state;
    const auto xs = column(sparse.trajectory, name), xd = column(dense.trajectory, name);
    for (std::size_t i = 1; i < grid.times.size(); ++i) {
      const double t = grid.times[i], lambda = t / 0.1;
      const auto [p, density] = erlang(k, lambda);
      CAPTURE(t);
      CHECK(xs[i] == Approx(p).margin(1e-7));
      CHECK(xs[i] == Approx(xd[i]).margin(1e-8));
      const double ds = sparse.state_sensitivities[i](Eigen::Index(state), 0);
      const double dd = dense.state_sensitivities[i](Eigen::Index(state), 0);
      const double exact = -t / (0.1 * 0.1) * density;
      CHECK(ds == Approx(exact).margin(1e-5 * (1 + std::abs(exact))));
      CHECK(ds == Approx(dd).margin(1e-6 * (1 + std::abs(exact))));
    }
  }
}

TEST_CASE("KLU needs the model's Jacobian: without it the simulation stays on dense LU", "[sparse]") {
  auto model = lag_chain();
  const auto grid = runtime::OutputGrid::uniform(0, 20, 10);
  const auto p = model->info().default_parameters();
  const auto r = runtime::simulate(*model, {}, p, grid, with(runtime::LinearSolverChoice::sparse, false));
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(r.statistics.sparse_linear_solver);
  auto no_model_jacobian = with(runtime::LinearSolverChoice::sparse, false);
  no_model_jacobian.use_model_jacobian = false;  // CVODES' difference quotients need a dense matrix
  const auto d = runtime::simulate(*model, {}, p, grid, no_model_jacobian);
  INFO(d.message);
  REQUIRE(d.ok());
  CHECK_FALSE(d.statistics.sparse_linear_solver);
  CHECK(max_abs_difference(column(r.trajectory, "x[150]"), column(d.trajectory, "x[150]")) < 1e-7);
}

TEST_CASE("a Jacobian taken by differences fills KLU's pattern (RegularisedFriction)", "[sparse][robustness]") {
  auto model = compiled_model("e2e_regularised_friction", {{kData + "RegularisedFriction.mo", "", {}, true}, {}});
  const auto grid = runtime::OutputGrid::uniform(0, 1.5, 150);
  runtime::SimulationResult runs[2];
  int i = 0;
  for (auto choice : {runtime::LinearSolverChoice::sparse, runtime::LinearSolverChoice::dense}) {
    runs[i] = runtime::simulate(*model, {}, model->info().default_parameters(), grid, with(choice, false));
    INFO(runs[i].message);
    REQUIRE(runs[i].ok());
    CHECK(runs[i].statistics.difference_jacobians > 0);
    ++i;
  }
  CHECK(runs[0].statistics.sparse_linear_solver);
  // Two states: automatic keeps dense LU.
  const auto automatic = runtime::simulate(*model, {}, model->info().default_parameters(), grid,
                                           with(runtime::LinearSolverChoice::automatic, false));
  REQUIRE(automatic.ok());
  CHECK_FALSE(automatic.statistics.sparse_linear_solver);
  CHECK(max_abs_difference(column(runs[0].trajectory, "v"), column(runs[1].trajectory, "v")) < 1e-7);
  CHECK(max_abs_difference(column(runs[0].trajectory, "s"), column(runs[1].trajectory, "s")) < 1e-7);
}
