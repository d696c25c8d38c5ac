// The initial system at the start time with the inputs' values there
// (tests/e2e/data/initial/InputSteadyState.mo): steady states under u(t0),
// linear and through Newton, for t0 = 0 and t0 ≠ 0, their sensitivities
// against finite differences, a collocation study refused where the start
// values would depend on a free control, and an estimation through a steady
// start under a given input.
#include <cmath>
#include <fstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "e2e/cli.hpp"
#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

const std::string kInit = kData + "initial/";

tools::ModelSource steady_source() { return {kInit + "InputSteadyState.mo", "InputSteadyState", {}, true}; }

/// The root of w^3 + w = c (Newton from 1, to rounding).
double cubic_root(double c) {
  double w = 1;
  for (int k = 0; k < 100; ++k) w -= (w * w * w + w - c) / (3 * w * w + 1);
  return w;
}

}  // namespace

TEST_CASE("initial equations der(x) = 0 are solved with the inputs at t0, not at 0") {
  auto model = compiled_model("e2e_init_InputSteadyState", {steady_source(), {}});
  const auto& info = model->info();
  REQUIRE(info.input_in_initial == std::vector<bool>{true});
  const std::size_t ix = info.state_index("x").value(), iw = info.state_index("w").value();
  for (const double t0 : {0.0, 0.5}) {
    INFO("t0 = " << t0);
    // u = 10 until t = 1, then 12: x rests at 5.5, then relaxes to 6.5.
    runtime::Inputs inputs;
    inputs.add(runtime::step_input(2.0, 1.0, 10.0));
    const auto grid = runtime::OutputGrid::uniform(t0, 2.0, 30);
    const auto r = runtime::simulate(*model, inputs, info.default_parameters(), grid, tight());
    INFO(r.message);
    REQUIRE(r.ok());
    const auto x = column(r.trajectory, "x"), w = column(r.trajectory, "w");
    CHECK(x.front() == Approx(5.5).epsilon(1e-12));
    CHECK(w.front() == Approx(2.0).epsilon(1e-10));  // 8 + 2 = 10
    for (std::size_t k = 0; k < grid.times.size(); ++k) {
      const double t = grid.times[k];
      INFO("t = " << t);
      const double exact = t < 1 ? 5.5 : 6.5 - std::exp(-2 * (t - 1));
      CHECK(std::fabs(x[k] - exact) < 1e-6);
      if (t < 1) CHECK(std::fabs(w[k] - 2.0) < 1e-6);
    }
    std::vector<double> x0(info.states.size()), u0{10.0 + t0};
    model->initial_state(t0, u0, info.default_parameters(), x0);
    CHECK(x0[ix] == Approx((1 + 10 + t0) / 2).epsilon(1e-12));
    CHECK(x0[iw] == Approx(cubic_root(10 + t0)).epsilon(1e-10));
  }
  // Without inputs (the two-argument form) the initial system sees u = 0.
  std::vector<double> x0(info.states.size());
  model->initial_state(info.default_parameters(), x0);
  CHECK(x0[ix] == Approx(0.5).epsilon(1e-12));
}

TEST_CASE("sensitivities of a start value that depends on u(t0) equal finite differences") {
  auto augmented = compiled_model("e2e_init_InputSteadyState_d_a", {steady_source(), {"a"}});
  auto plain = compiled_model("e2e_init_InputSteadyState", {steady_source(), {}});
  const auto grid = runtime::OutputGrid::uniform(0.25, 2.0, 14);
  auto options = tight();
  options.sensitivities.method = runtime::SensitivityMethod::model_states;
  options.sensitivities.parameters = {parameter(augmented->info(), "a")};
  runtime::Inputs inputs;
  inputs.add(runtime::sine_input(1.0, 0.5, 0.0, 10.0));
  const auto r = runtime::simulate(*augmented, inputs, augmented->info().default_parameters(), grid, options);
  INFO(r.message);
  REQUIRE(r.ok());
  const std::size_t row = augmented->info().state_index("x").value();
  // dx0/da = -(b + u(t0)) / a^2 at t0 = 0.25, u(t0) = 10 + sin(pi/4).
  const double u0 = 10 + std::sin(2 * M_PI * 0.5 * 0.25);
  CHECK(r.state_sensitivities.front()(static_cast<Eigen::Index>(row), 0) == Approx(-(1 + u0) / 4).epsilon(1e-8));
  auto p = plain->info().default_parameters();
  const std::size_t k = parameter(plain->info(), "a");
  const double h = 1e-5;
  std::vector<std::vector<double>> x;
  for (const double sign : {1.0, -1.0}) {
    auto q = p;
    q[k] += sign * h;
    const auto s = runtime::simulate(*plain, inputs, q, grid, tight());
    REQUIRE(s.ok());
    x.push_back(column(s.trajectory, "x"));
  }
  for (std::size_t t = 0; t < grid.times.size(); ++t) {
    INFO("t = " << grid.times[t]);
    const double fd = (x[0][t] - x[1][t]) / (2 * h);
    CHECK(std::fabs(r.state_sensitivities[t](static_cast<Eigen::Index>(row), 0) - fd) <= 1e-6 * std::max(1.0, std::fabs(fd)));
  }
}

TEST_CASE("a collocation study whose initial system reads a free control is refused with the reason") {
  const fs::path dir = scratch("input_steady_control");
  const Run r = morun(quoted(kInit + "InputSteadyControl.mop") + " -o " + quoted((dir / "out").string()), dir);
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("InputSteadyControl.mop:5:14: error: the initial system reads input 'u'") != std::string::npos);
  CHECK(!fs::exists(dir / "out" / "summary.json"));
}

TEST_CASE("an estimation through a steady start under a given input recovers the parameter") {
  // Noise-free x of InputSteadyState at a = 2.5, u = 10 then 12 from t = 1:
  // x = 11/2.5 = 4.4 until t = 1, then 5.2 - 0.8 exp(-2.5 (t - 1)). Started
  // at u = 0 instead, x0 = b/a, and no value of a fits.
  const fs::path dir = scratch("input_steady_estimation");
  {
    std::ofstream u(dir / "u.csv");
    u << "time,u\n0,10\n1,12\n2,12\n";
    std::ofstream x(dir / "x.csv");
    x << "time,x\n";
    for (int k = 0; k <= 40; ++k) {
      const double t = 0.05 * k;
      x << t << "," << (t <= 1 ? 4.4 : 5.2 - 0.8 * std::exp(-2.5 * (t - 1))) << "\n";
    }
    std::ofstream study(dir / "Estimate.opt");
    study << "optimization Estimate(startTime = 0)\n"
             "  extends InputSteadyState(a(free = true, min = 0.5, max = 10, initialGuess = 1.5));\n"
             "annotation(__mocompile(task = \"estimation\", outputs = {x}, sigma = {0.01},\n"
             "  data = {\"x.csv\"}, inputs = {\"u=pwc:u.csv\"}, n_e = 40, n_cp = 3));\n"
             "end Estimate;\n";
  }
  const Run r = morun(quoted((dir / "Estimate.opt").string()) + " -L " + quoted(kInit + "InputSteadyState.mo") +
                          " -o " + quoted((dir / "out").string()),
                      dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const auto s = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
  REQUIRE(s["estimates"].size() == 1);
  CHECK(double(s["estimates"][0]["estimate"]) == Approx(2.5).margin(1e-6));
}
