// Functions that branch on their own intermediate values: inlined as trees
// they grow by a factor per statement (5^14 terms for BranchyFunctions.stages);
// their large values become variables of the model (flatten_intermediates.cpp).
// tests/e2e/data/BranchyFunctions.mo against the same algorithms run here,
// and sensitivities through them against finite differences.
#include <algorithm>
#include <cmath>
#include <string>

#include "e2e/support.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

/// BranchyFunctions.stages, as written there.
double stages(double x, double a, int n = 14) {
  double s = x;
  for (int i = 0; i < n; ++i)
    s = s < 0.5 ? a * s * (1 - s) + 0.1 * x : 0.25 * a + 0.1 * x - 0.3 * (s - 0.5) * (s + 0.2);
  return s;
}

/// BranchyFunctions.secant, as written there.
double secant(double u, double v) {
  const double d = u - v;
  double q = std::fabs(d) > 1e-3 ? (std::sin(u) - std::sin(v)) / d : std::cos((u + v) / 2);
  for (int i = 0; i < 5; ++i) q = q + 0.01 * q * (1 - q * q);
  return q;
}

runtime::OutputGrid grid() { return runtime::OutputGrid::uniform(0, 4, 40); }

}  // namespace

TEST_CASE("a function that branches on its own values 14 times is inlined through intermediates",
          "[e2e][intermediates]") {
  const auto r = run_data_model("e2e_branchy_stages", "BranchyFunctions.mo", "BranchyFunctions.Stages", 4, 40);
  const auto t = r->times();
  const auto x = (*r)("x");
  const auto y = (*r)("y");
  for (std::size_t k = 0; k < t.size(); ++k) {
    INFO("t = " << t[k]);
    CHECK(x[k] == Approx(0.3 * t[k]).margin(1e-9));
    CHECK(y[k] == Approx(stages(x[k], 2.5)).margin(1e-9));
  }
}

TEST_CASE("sensitivities through intermediates equal finite differences", "[e2e][intermediates]") {
  const tools::ModelSource source{kData + "BranchyFunctions.mo", "BranchyFunctions.Stages", {}, true};
  auto plain = compiled_model("e2e_branchy_stages_plain", {source, {}});
  auto augmented = compiled_model("e2e_branchy_stages_sens", {source, {"a"}});
  runtime::SimulationOptions o = tight();
  o.sensitivities.method = runtime::SensitivityMethod::model_states;
  const auto s = runtime::simulate(*augmented, runtime::Inputs{}, augmented->info().default_parameters(), grid(), o);
  INFO(s.message);
  REQUIRE(s.ok());
  const auto p = plain->info().default_parameters();
  const std::size_t k = parameter(plain->info(), "a");
  const auto fds = richardson_difference(*plain, p, k, 1e-4, grid(), "z");
  const auto mine = column(s.trajectory, "d(z)/d(a)");
  const auto [worst, scale] = deviation_after_t0(mine, fds);
  INFO("d(z)/d(a): max error " << worst << " of " << scale);
  CHECK(scale > 1e-2);
  CHECK(worst < 1e-5 * scale);
}

TEST_CASE("an intermediate computed in a branch is not computed outside it", "[e2e][intermediates]") {
  // u = sin t: the branch's division by u is 0/0 at t = 0 and near t = pi.
  const auto r = run_data_model("e2e_branchy_secant", "BranchyFunctions.mo", "BranchyFunctions.Secant", 4, 40);
  const auto t = r->times();
  const auto u = (*r)("u");
  const auto q = (*r)("q");
  for (std::size_t k = 0; k < t.size(); ++k) {
    INFO("t = " << t[k]);
    CHECK(u[k] == Approx(std::sin(t[k])).margin(1e-7));
    CHECK(std::isfinite(q[k]));
    CHECK(q[k] == Approx(secant(u[k], 0)).margin(1e-9));
  }
  // Every column, the intermediates' included (0 outside their branch):
  // unguarded, the branch's (sin u - sin 0)/u is NaN at t = 0.
  const auto& table = r->result.trajectory;
  for (const auto& name : table.names()) {
    const auto values = table.column(name);
    INFO(name);
    CHECK(std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); }));
  }
}

TEST_CASE("sensitivities through an intermediate computed in a branch equal finite differences",
          "[e2e][intermediates]") {
  const tools::ModelSource source{kData + "BranchyFunctions.mo", "BranchyFunctions.Secant", {}, true};
  auto plain = compiled_model("e2e_branchy_secant_plain", {source, {}});
  auto augmented = compiled_model("e2e_branchy_secant_sens", {source, {"k"}});
  runtime::SimulationOptions o = tight();
  o.sensitivities.method = runtime::SensitivityMethod::model_states;
  const auto s = runtime::simulate(*augmented, runtime::Inputs{}, augmented->info().default_parameters(), grid(), o);
  INFO(s.message);
  REQUIRE(s.ok());
  const auto p = plain->info().default_parameters();
  const std::size_t k = parameter(plain->info(), "k");
  const auto fds = richardson_difference(*plain, p, k, 1e-4, grid(), "w");
  const auto mine = column(s.trajectory, "d(w)/d(k)");
  const auto [worst, scale] = deviation_after_t0(mine, fds);
  INFO("d(w)/d(k): max error " << worst << " of " << scale);
  CHECK(scale > 1e-2);
  CHECK(worst < 1e-5 * scale);
}
