// Functions that branch on their own intermediate values: inlined as trees
// they grow by a factor per statement (5^14 terms for BranchyFunctions.stages);
// their large values become variables of the model (flatten_intermediates.cpp).
// tests/e2e/data/BranchyFunctions.mo and RegFun3Sweep.mo (the MSL's
// Fluid.Utilities.regFun3) against the same algorithms run here, and
// sensitivities through them against finite differences.
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <tuple>
#include <vector>

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

/// Modelica.Fluid.Utilities.regFun3 of MSL 3.2.2, statement for statement,
/// and which of its ways it took.
struct RegFun3 {
  double y, c;
  enum Way { Horizontal, Cubic, Pieces } way = Cubic;
};
RegFun3 reg_fun3(double x, double x0, double x1, double y0, double y1, double y0d, double y1d) {
  constexpr double eps = 2.220446049250313e-16;
  const double h0 = x1 - x0, Delta0 = (y1 - y0) / h0;
  if (std::fabs(Delta0) <= 0) return {y0 + Delta0 * (x - x0), 0, RegFun3::Horizontal};
  if (std::fabs(y1d + y0d - 2 * Delta0) < 100 * eps) {
    const double y = y0 + (x - x0) * (y0d + (x - x0) / h0 * ((-2 * y0d - y1d + 3 * Delta0) +
                                                             (x - x0) * (y0d + y1d - 2 * Delta0) / h0));
    const double aux01 = (x0 + x1) / 2;
    return {y, 3 * (y0d + y1d - 2 * Delta0) * std::pow(aux01 - x0, 2) / (h0 * h0) +
                   2 * (-2 * y0d - y1d + 3 * Delta0) * (aux01 - x0) / h0 + y0d};
  }
  const double xstar = 1.0 / 3 * (-3 * x0 * y0d - 3 * x0 * y1d + 6 * x0 * Delta0 - 2 * h0 * y0d - h0 * y1d +
                                  3 * h0 * Delta0) / (-y0d - y1d + 2 * Delta0);
  const double mu = xstar - x0, eta = x1 - xstar;
  const double omega = 3 * (y0d + y1d - 2 * Delta0) * std::pow(xstar - x0, 2) / (h0 * h0) +
                       2 * (-2 * y0d - y1d + 3 * Delta0) * (xstar - x0) / h0 + y0d;
  const double sign = Delta0 > 0 ? 1 : Delta0 < 0 ? -1 : 0;
  const double aux01 = 0.25 * sign * std::min(std::fabs(omega), std::fabs(Delta0));
  double aux02 = 0;
  bool single = false;
  if (std::fabs(y0d - y1d) <= 100 * eps) {
    aux02 = y0d;
    if (y1 > y0 + y0d * (x1 - x0)) single = true;
  } else if (std::fabs(y1d + y0d - 2 * Delta0) < 100 * eps) {
    aux02 = (6 * Delta0 * (y1d + y0d - 1.5 * Delta0) - y1d * y0d - y1d * y1d - y0d * y0d) *
            ((y1d + y0d - 2 * Delta0) >= 0 ? 1 : -1) * std::numeric_limits<double>::max();
  } else {
    aux02 = (6 * Delta0 * (y1d + y0d - 1.5 * Delta0) - y1d * y0d - y1d * y1d - y0d * y0d) /
            (3 * (y1d + y0d - 2 * Delta0));
  }
  if ((((mu > 0) && (eta < h0) && (Delta0 * omega <= 0)) || (std::fabs(aux01) < std::fabs(aux02) && aux02 * Delta0 >= 0) ||
       (std::fabs(aux01) < std::fabs(0.1 * Delta0))) && !single) {
    double c = aux01;
    if (std::fabs(c) < std::fabs(aux02) && aux02 * Delta0 >= 0) c = aux02;
    if (std::fabs(c) < std::fabs(0.1 * Delta0)) c = 0.1 * Delta0;
    const double theta0 = (y0d * mu + y1d * eta) / h0;
    if (std::fabs(theta0 - c) < 1e-6) c = (1 - 1e-6) * theta0;
    const double rho = 3 * (Delta0 - c) / (theta0 - c);
    const double mu_tilde = rho * mu, eta_tilde = rho * eta;
    const double xi1 = x0 + mu_tilde, xi2 = x1 - eta_tilde;
    const double a1 = (y0d - c) / std::max(mu_tilde * mu_tilde, 100 * eps);
    const double a2 = (y1d - c) / std::max(eta_tilde * eta_tilde, 100 * eps);
    const double const12 = y0 - a1 / 3 * std::pow(x0 - xi1, 3) - c * x0;
    const double const3 = y1 - a2 / 3 * std::pow(x1 - xi2, 3) - c * x1;
    if (x < xi1) return {a1 / 3 * std::pow(x - xi1, 3) + c * x + const12, c, RegFun3::Pieces};
    if (x < xi2) return {c * x + const12, c, RegFun3::Pieces};
    return {a2 / 3 * std::pow(x - xi2, 3) + c * x + const3, c, RegFun3::Pieces};
  }
  const double y = y0 + (x - x0) * (y0d + (x - x0) / h0 * ((-2 * y0d - y1d + 3 * Delta0) +
                                                           (x - x0) * (y0d + y1d - 2 * Delta0) / h0));
  const double mid = (x0 + x1) / 2;
  return {y, 3 * (y0d + y1d - 2 * Delta0) * std::pow(mid - x0, 2) / (h0 * h0) +
                 2 * (-2 * y0d - y1d + 3 * Delta0) * (mid - x0) / h0 + y0d};
}

runtime::OutputGrid grid() { return runtime::OutputGrid::uniform(0, 4, 40); }

/// Simulates `augmented` (sensitivities to `names`) and CHECKs d(state)/d(name)
/// against Richardson finite differences of `plain`, to 1e-5 of its largest value.
void check_sensitivities(runtime::Model& plain, runtime::Model& augmented, const std::vector<std::string>& names,
                         const std::string& state, const runtime::OutputGrid& g) {
  runtime::SimulationOptions o = tight();
  o.sensitivities.method = runtime::SensitivityMethod::model_states;
  const auto s = runtime::simulate(augmented, runtime::Inputs{}, augmented.info().default_parameters(), g, o);
  INFO(s.message);
  REQUIRE(s.ok());
  const auto p = plain.info().default_parameters();
  for (const auto& name : names) {
    const std::size_t k = parameter(plain.info(), name);
    const auto fds = richardson_difference(plain, p, k, 1e-4, g, state);
    const auto mine = column(s.trajectory, "d(" + state + ")/d(" + name + ")");
    const auto [worst, scale] = deviation_after_t0(mine, fds);
    INFO("d(" << state << ")/d(" << name << "): max error " << worst << " of " << scale);
    CHECK(scale > 1e-2);
    CHECK(worst < 1e-5 * scale);
  }
}

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
  check_sensitivities(*plain, *augmented, {"a"}, "z", grid());
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
  check_sensitivities(*plain, *augmented, {"k"}, "w", grid());
}

TEST_CASE("the MSL's Fluid.Utilities.regFun3 inlined through intermediates equals its algorithm run here",
          "[e2e][intermediates][msl]") {
  const auto r = run_data_model("e2e_regfun3_sweep", "RegFun3Sweep.mo", "RegFun3Sweep", 1, 50, true);
  if (!r) {
    SUCCEED("skipped: no MSL in ../shared");
    return;
  }
  const auto t = r->times();
  const auto x = (*r)("x"), a = (*r)("a");
  const auto y = (*r)("y"), c = (*r)("c"), ya = (*r)("ya"), ca = (*r)("ca"), yb = (*r)("yb"), cb = (*r)("cb");
  std::set<RegFun3::Way> ways;
  for (std::size_t k = 0; k < t.size(); ++k) {
    INFO("t = " << t[k]);
    const double s = a[k];
    for (const auto& [got_y, got_c, want] :
         {std::tuple{y[k], c[k], reg_fun3(x[k], -1, 2, -2, 3, 0.5, 4)},
          std::tuple{ya[k], ca[k], reg_fun3(x[k], -1 + s, 2 + s, -2 + s, 3 + s, 0.5 + s, 4 + s)},
          std::tuple{yb[k], cb[k], reg_fun3(x[k], -1, 2, -2, 3, 0.1 + s, 0.1)}}) {
      CHECK(got_y == Approx(want.y).margin(1e-9));
      CHECK(got_c == Approx(want.c).margin(1e-9));
      ways.insert(want.way);
    }
  }
  CHECK(ways.count(RegFun3::Cubic));   // one cubic, monotonic as it is
  CHECK(ways.count(RegFun3::Pieces));  // two cubics and a line between
  // The interpolation's own properties: the end points (t = 0 and 1).
  CHECK(y.front() == Approx(-2).margin(1e-9));
  CHECK(y.back() == Approx(3).margin(1e-9));
  CHECK(yb.back() == Approx(3).margin(1e-9));
}

TEST_CASE("sensitivities through regFun3's parameter intermediates equal finite differences",
          "[e2e][intermediates][msl]") {
  // With parameter end points and slopes, regFun3's values of them alone are
  // parameters computed from them (bindings): d0 reaches y through those.
  const tools::ModelSource source{kData + "RegFun3Sweep.mo", "RegFun3Sweep", {}, true};
  auto plain = msl_compiled_model("e2e_regfun3_plain", {source, {}});
  if (!plain) {
    SUCCEED("skipped: no MSL in ../shared");
    return;
  }
  auto augmented = msl_compiled_model("e2e_regfun3_sens", {source, {"d0", "y1"}});
  REQUIRE(augmented);
  check_sensitivities(*plain, *augmented, {"d0", "y1"}, "z", runtime::OutputGrid::uniform(0, 1, 20));
}
