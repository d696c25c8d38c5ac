// Algorithm sections and functions executed on expressions (frontend
// flatten_algorithms.cpp, flatten_functions.cpp), end to end on an own model
// (data/algorithms/AlgorithmDamper.mo): reassignments, a for accumulator, an
// `if` on a varying condition and a while-loop on a varying condition in a
// function with two outputs. Generated code equals the interpreter, Jacobians
// equal finite differences, and sensitivities through the branches and the
// table equal central differences of re-simulations.
#include <random>

#include "codegen/jacobian_check.hpp"
#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"
#include "mo/symbolic/ode_interpreter.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

tools::ModelSource damper() { return {kData + "algorithms/AlgorithmDamper.mo", "", {}, true}; }

const runtime::OutputGrid& grid() {
  static const runtime::OutputGrid g = runtime::OutputGrid::uniform(0, 4, 80);
  return g;
}

}  // namespace

TEST_CASE("algorithms: generated code equals the interpreter - Jacobians equal differences", "[e2e][algorithms]") {
  const symbolic::OdeModel m = lower_spec({damper(), {}});
  symbolic::OdeInterpreter interpreter(m);
  auto model = compiled_model("e2e_algorithm_damper", {damper(), {}});
  const auto p = model->info().default_parameters();
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> pos(-3.5, 3.5), vel(-2, 2);
  REQUIRE(model->info().num_base_states() == 2);
  for (int k = 0; k < 16; ++k) {
    const std::vector<double> x{pos(rng), vel(rng)};
    // Differences across a kink (v = 0, a table breakpoint) are not derivatives.
    bool near_kink = std::fabs(x[1]) < 1e-2;
    for (double b : {-1.0, 0.0, 1.0}) near_kink = near_kink || std::fabs(x[0] - b) < 1e-2;
    if (near_kink) continue;
    std::vector<double> xdot(2), y(model->info().outputs.size());
    model->rhs(0.5, x, {}, p, xdot);
    model->outputs(0.5, x, {}, p, y);
    const auto xdot_ref = interpreter.rhs(0.5, x, {}, p);
    const auto y_ref = interpreter.outputs(0.5, x, {}, p);
    INFO("x = " << x[0] << ", v = " << x[1]);
    for (std::size_t j = 0; j < 2; ++j) CHECK(xdot[j] == Approx(xdot_ref[j]).epsilon(1e-12).margin(1e-14));
    for (std::size_t j = 0; j < y.size(); ++j) CHECK(y[j] == Approx(y_ref[j]).epsilon(1e-12).margin(1e-14));
    // The force by hand: -k x - (1 or a) c v (1 + 1/2 + 1/3) - table(x) v.
    const double xs[] = {-3, -1, 0, 1, 3}, ys[] = {1, 0.25, 0, 0.25, 1};
    int i = 0;
    while (i < 3 && x[0] >= xs[i + 1]) ++i;
    const double table = ys[i] + (ys[i + 1] - ys[i]) * (x[0] - xs[i]) / (xs[i + 1] - xs[i]);
    const double damping = 0.1 * x[1] * (1 + 0.5 + 1.0 / 3) * (x[1] > 0 ? 1 : 1.5);
    CHECK(xdot[1] == Approx(-2 * x[0] - damping - table * x[1]).epsilon(1e-12));
    codegen::test::check_jacobians(*model, 0.5, x, {}, p, 1e-5);
  }
}

TEST_CASE("algorithms: sensitivities through the branches and the table equal finite differences",
          "[e2e][algorithms]") {
  const std::vector<std::string> names{"k", "c", "a", "s"};
  auto plain = compiled_model("e2e_algorithm_damper", {damper(), {}});
  auto augmented = compiled_model("e2e_algorithm_damper_sens", {damper(), names});
  const auto& info = augmented->info();
  runtime::SimulationOptions o = tight();
  o.sensitivities.method = runtime::SensitivityMethod::model_states;
  const auto s = runtime::simulate(*augmented, runtime::Inputs{}, info.default_parameters(), grid(), o);
  INFO(s.message);
  REQUIRE(s.ok());
  const auto p = plain->info().default_parameters();
  // The run crosses v = 0 and the table's breakpoints: not a trivial path.
  const auto v = column(s.trajectory, "v");
  CHECK(*std::min_element(v.begin(), v.end()) < -0.3);
  CHECK(*std::max_element(v.begin(), v.end()) > 0.3);
  for (std::size_t j = 0; j < names.size(); ++j) {
    const std::size_t k = parameter(plain->info(), names[j]);
    const double h = 1e-3 * std::fabs(p[k]);
    for (const char* name : {"x", "v"}) {
      const auto fds = richardson_difference(*plain, p, k, h, grid(), name);
      const auto mine = column(s.trajectory, "d(" + std::string(name) + ")/d(" + names[j] + ")");
      const auto [worst, scale] = deviation_after_t0(mine, fds);
      INFO("d(" << name << ")/d(" << names[j] << "): max error " << worst << " of " << scale);
      CHECK(scale > 1e-3);
      CHECK(worst < 1e-4 * scale);
    }
  }
}

TEST_CASE("a for-loop left by a break under a varying condition (BreakOnSignal)") {
  auto model = compiled_model("e2e_break_on_signal", {{kData + "algorithms/BreakOnSignal.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  // At t: count = the largest k <= 4 with k (k + 1) / 2 <= 10 t.
  for (const double t : {0.05, 0.15, 0.35, 0.65, 0.95, 1.2}) {
    const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, t, 2), tight());
    INFO(r.message << " at t = " << t);
    REQUIRE(r.ok());
    int k = 0;
    while (k < 4 && (k + 1) * (k + 2) / 2 <= 10 * t) ++k;
    CHECK(discrete_value(*model, "count") == k);
    CHECK(discrete_value(*model, "last") == k);
  }
}
