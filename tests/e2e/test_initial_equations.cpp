// Consistent initialisation (issue 10): `initial equation` sections and
// `fixed` starts solved at t0 by the lowered initial system, with the start
// sensitivities ∂x0/∂p through it checked against finite differences of
// simulations.
#include <cmath>
#include <sstream>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"
#include "mo/symbolic/ode_interpreter.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

const std::string kInit = kData + "initial/";

tools::ModelSource source(const std::string& name) { return {kInit + name + ".mo", name, {}, true}; }

/// The pipeline's diagnostics for `name`, and whether lowering succeeded.
std::pair<bool, std::string> lower_text(const std::string& name) {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  auto flat = tools::load_flat_model(source(name), sources, diags);
  std::optional<symbolic::OdeModel> ode;
  if (flat) ode = tools::lower_model(*flat, diags);
  std::ostringstream printed;
  diags.print(printed);
  return {ode.has_value(), printed.str()};
}

/// State `name` of `model` over the grid at parameters p.
std::vector<double> run(runtime::Model& model, std::span<const double> p, const std::string& name,
                        const runtime::OutputGrid& grid) {
  const auto r = runtime::simulate(model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  return column(r.trajectory, name);
}

/// Generated sensitivity d(state)/d(par) against central differences of
/// two simulations, at every grid time (t0 included: S(t0) = dx0/dp).
void check_sensitivity(const std::string& model_name, const std::string& par,
                       const std::vector<std::string>& states, double tolerance) {
  auto plain = compiled_model("e2e_init_" + model_name, {source(model_name), {}});
  auto augmented = compiled_model("e2e_init_" + model_name + "_d_" + par, {source(model_name), {par}});
  const auto grid = runtime::OutputGrid::uniform(0, 2, 20);
  auto options = tight();
  options.sensitivities.method = runtime::SensitivityMethod::model_states;
  options.sensitivities.parameters = {parameter(augmented->info(), par)};
  const auto r = runtime::simulate(*augmented, {}, augmented->info().default_parameters(), grid, options);
  INFO(r.message);
  REQUIRE(r.ok());
  const std::size_t k = parameter(plain->info(), par);
  auto p = plain->info().default_parameters();
  const double h = 1e-5 * std::max(1.0, std::abs(p[k]));
  p[k] += h;
  std::vector<std::vector<double>> up, down;
  for (const auto& s : states) up.push_back(run(*plain, p, s, grid));
  p[k] -= 2 * h;
  for (const auto& s : states) down.push_back(run(*plain, p, s, grid));
  for (std::size_t i = 0; i < states.size(); ++i) {
    const auto index = augmented->info().state_index(states[i]);
    REQUIRE(index);
    const auto row = static_cast<Eigen::Index>(*index);
    REQUIRE(row < static_cast<Eigen::Index>(r.state_sensitivities.front().rows()));
    for (std::size_t t = 0; t < grid.times.size(); ++t) {
      const double fd = (up[i][t] - down[i][t]) / (2 * h);
      INFO(states[i] << " at t = " << grid.times[t]);
      CHECK(std::abs(r.state_sensitivities[t](row, 0) - fd) <= tolerance * std::max(1.0, std::abs(fd)));
    }
  }
}

}  // namespace

TEST_CASE("initial equation der(x) = 0 starts in equilibrium, with dx0/db = 1/a") {
  auto model = compiled_model("e2e_init_SteadyState", {source("SteadyState"), {}});
  std::vector<double> x0(1);
  model->initial_state(model->info().default_parameters(), x0);
  CHECK(x0[0] == Approx(1.5).epsilon(1e-14));  // (b + y(0)) / a
  check_sensitivity("SteadyState", "b", {"x"}, 1e-6);
  check_sensitivity("SteadyState", "a", {"x"}, 1e-6);
}

TEST_CASE("a nonlinear initial equation is solved by Newton at t0 - sensitivities through it") {
  auto model = compiled_model("e2e_init_NonlinearStart", {source("NonlinearStart"), {}});
  std::vector<double> x0(2);
  model->initial_state(model->info().default_parameters(), x0);
  const std::size_t ix = model->info().state_index("x").value();
  const std::size_t iv = model->info().state_index("v").value();
  CHECK(x0[ix] == Approx(2.0).epsilon(1e-12));
  CHECK(x0[iv] == Approx(0.1).epsilon(1e-14));
  // dx0/dk = 1 / (3 x0^2 + 1) = 1/13, then carried by the dynamics.
  check_sensitivity("NonlinearStart", "k", {"x", "v"}, 1e-5);
  check_sensitivity("NonlinearStart", "c", {"x", "v"}, 1e-5);
}

TEST_CASE("an under-determined initial system keeps the free states at their start values, with a warning") {
  const auto [ok, text] = lower_text("UnderDetermined");
  INFO(text);
  REQUIRE(ok);
  CHECK(text.find("warning: the initial equations leave 1 state(s) free; they start at their start values: y") !=
        std::string::npos);
  auto model = compiled_model("e2e_init_UnderDetermined", {source("UnderDetermined"), {}});
  std::vector<double> x0(2);
  model->initial_state(model->info().default_parameters(), x0);
  const std::size_t ix = model->info().state_index("x").value();
  CHECK(x0[ix] == Approx(0.25).epsilon(1e-14));
  CHECK(x0[1 - ix] == Approx(4.0).epsilon(1e-14));
}

TEST_CASE("an over-determined initial system is an error naming the equation") {
  const auto [ok, text] = lower_text("OverDetermined");
  INFO(text);
  CHECK_FALSE(ok);
  CHECK(text.find("OverDetermined.mo:5:3: error: the initial system is over-determined") != std::string::npos);
  CHECK(text.find("states declared fixed = true (each adds x = start): x") != std::string::npos);
}

TEST_CASE("inherited and array initial equations determine every state (interpreter, no compiler)") {
  const tools::ModelSource src{std::string(MO_SOURCE_DIR) + "/tests/frontend/data/arrays/InheritedInitial.mo",
                               "InheritedInitial", {}, true};
  const symbolic::OdeModel m = lower_spec({src, {}});
  std::vector<double> p;
  for (const auto& par : m.parameters) p.push_back(par.value);
  const std::vector<double> x0 = symbolic::OdeInterpreter(m).initial_state(p);
  REQUIRE(x0.size() == 3);
  CHECK(x0[m.state_index("x[1]").value()] == Approx(0.5).epsilon(1e-14));  // 1 - a x1 = 0
  CHECK(x0[m.state_index("y").value()] == Approx(2.0).epsilon(1e-14));     // y = a
  CHECK(x0[m.state_index("x[2]").value()] == Approx(2.0).epsilon(1e-14));  // y - x2 = 0
}

TEST_CASE("a fixed = false parameter is computed by the initial system - sensitivities through it") {
  const auto [ok, text] = lower_text("FreeParameter");
  INFO(text);
  REQUIRE(ok);
  CHECK(text.find("warning") == std::string::npos);
  auto model = compiled_model("e2e_init_FreeParameter", {source("FreeParameter"), {}});
  const auto p = model->info().default_parameters();
  const auto grid = runtime::OutputGrid::uniform(0, 2, 20);
  const auto x = run(*model, p, "x", grid), T_final = run(*model, p, "T_final", grid),
             tau = run(*model, p, "tau", grid);
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    INFO("t = " << grid.times[k]);
    CHECK(T_final[k] == Approx(6.0).epsilon(1e-12));
    CHECK(tau[k] == Approx(2.0).epsilon(1e-10));
    CHECK(x[k] == Approx(2 * std::exp(-grid.times[k] / 2)).epsilon(1e-8));
  }
  // A computed parameter is no parameter of the model: it cannot be set.
  CHECK_FALSE(model->info().parameter_index("tau"));
  check_sensitivity("FreeParameter", "r", {"x", "tau"}, 1e-5);  // tau = 2/r
  check_sensitivity("FreeParameter", "c", {"T_final"}, 1e-6);   // T_final = 3c
}

TEST_CASE("fixed = false parameters under Evaluate = true, and Boolean and Integer ones, are computed at t0") {
  const auto [ok, text] = lower_text("FreeParameterKinds");
  INFO(text);
  REQUIRE(ok);
  CHECK(text.find("warning") == std::string::npos);  // the Boolean's equation used to be ignored
  auto model = compiled_model("e2e_init_FreeParameterKinds", {source("FreeParameterKinds"), {}});
  const auto p = model->info().default_parameters();
  const auto grid = runtime::OutputGrid::uniform(0, 1, 10);
  const auto x = run(*model, p, "x", grid), z = run(*model, p, "z", grid), y = run(*model, p, "y", grid);
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double t = grid.times[k];
    INFO("t = " << t);
    CHECK(x[k] == Approx(2 * std::exp(-t)).epsilon(1e-7));
    CHECK(z[k] == Approx(4 * t).margin(1e-9));
    CHECK(y[k] == Approx(6 * t).margin(1e-9));
  }
  CHECK(discrete_value(*model, "positive") == 1.0);
  CHECK(discrete_value(*model, "n") == 6.0);
}

TEST_CASE("a fixed = true variable that is not a state sets the initial state without initial equations") {
  const symbolic::OdeModel m = lower_spec({source("FixedAlgebraic"), {}});
  std::vector<double> p;
  for (const auto& par : m.parameters) p.push_back(par.value);
  const std::vector<double> x0 = symbolic::OdeInterpreter(m).initial_state(p);
  REQUIRE(x0.size() == 1);
  CHECK(x0[m.state_index("x").value()] == Approx(2.0).epsilon(1e-14));  // y = 2 x = 4
}

TEST_CASE("a fixed = true variable that is not a state gives way to a fixed state, with a warning") {
  const auto [ok, text] = lower_text("FixedRedundant");
  INFO(text);
  REQUIRE(ok);
  CHECK(text.find("warning: 1 variable(s) declared fixed = true are not states") != std::string::npos);
  CHECK(text.find("their start values are not imposed: y") != std::string::npos);
  const symbolic::OdeModel m = lower_spec({source("FixedRedundant"), {}});
  std::vector<double> p;
  for (const auto& par : m.parameters) p.push_back(par.value);
  const std::vector<double> x0 = symbolic::OdeInterpreter(m).initial_state(p);
  CHECK(x0[m.state_index("x").value()] == Approx(1.0).epsilon(1e-14));
}

TEST_CASE("a fixed = true variable that became a state's derivative is an initial equation") {
  const auto [ok, text] = lower_text("FixedDerivative");
  INFO(text);
  REQUIRE(ok);
  CHECK(text.find("leave 1 state(s) free") == std::string::npos);
  const symbolic::OdeModel m = lower_spec({source("FixedDerivative"), {}});
  std::vector<double> p;
  for (const auto& par : m.parameters) p.push_back(par.value);
  const std::vector<double> x0 = symbolic::OdeInterpreter(m).initial_state(p);
  REQUIRE(x0.size() == 1);
  CHECK(x0[m.state_index("w").value()] == Approx(2.0).epsilon(1e-14));
}

TEST_CASE("a fixed velocity of a variable replaced by a relative position starts that position's derivative") {
  // s and v are eliminated for the preferred s_rel; v(fixed = true) must
  // follow to der(s_rel) (before, it started at 0 and the mass stood still).
  auto model = compiled_model("e2e_init_relative_states", {source("RelativeStates"), {}});
  const auto s_rel = [](double t) { return 1 - 0.4 * (1 - std::exp(-25 * t)); };
  simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 0.2, 40), "s_rel", s_rel, 1e-7);
}

TEST_CASE("a variable its equation leaves undetermined at t0 keeps its start - Newton steps off a singular Jacobian") {
  const auto [ok, text] = lower_text("SaturatingCoil");
  INFO(text);
  REQUIRE(ok);
  CHECK(text.find("warning: 'L' is left undetermined at the initial point") != std::string::npos);
  auto model = compiled_model("e2e_init_SaturatingCoil", {source("SaturatingCoil"), {}});
  const auto grid = runtime::OutputGrid::uniform(0, 6, 60);
  const auto psi = run(*model, model->info().default_parameters(), "psi", grid);
  // The current of flux psi: Linf i + (L0 - Linf) I0 atan(i/I0) = psi, by bisection.
  const auto current = [](double flux) {
    double lo = -10, hi = 10;
    for (int n = 0; n < 100; ++n) {
      const double mid = (lo + hi) / 2;
      (0.5 * mid + 1.5 * 0.25 * std::atan(mid / 0.25) < flux ? lo : hi) = mid;
    }
    return (lo + hi) / 2;
  };
  // der(psi) = cos(t) - R i(psi), R = 0.5, by classical Runge-Kutta (h = 1e-3).
  const auto f = [&](double t, double x) { return std::cos(t) - 0.5 * current(x); };
  double x = 0, t = 0;
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    for (const double h = 1e-3; t < grid.times[k] - h / 2; t += h) {
      const double k1 = f(t, x), k2 = f(t + h / 2, x + h / 2 * k1), k3 = f(t + h / 2, x + h / 2 * k2),
                   k4 = f(t + h, x + h * k3);
      x += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    INFO("t = " << grid.times[k]);
    CHECK(psi[k] == Approx(x).margin(1e-8));
  }
}

TEST_CASE("der() in an initial equation of a variable the model does not differentiate", "[initial]") {
  // An eliminated alias (vR = R*i) and a value through a nonlinear block
  // (y + y^3 = i, z = sin y + y): both give the steady state i(0) = V/R.
  for (const std::string name : {"SteadyAlgebraic", "SteadyImplicit"}) {
    INFO(name);
    auto model = compiled_model("e2e_init_" + name, {source(name), {}});
    std::vector<double> x0(1);
    model->initial_state(model->info().default_parameters(), x0);
    CHECK(x0[0] == Approx(5.0).epsilon(1e-12));
    const auto grid = runtime::OutputGrid::uniform(0, 1, 10);
    for (double i : run(*model, model->info().default_parameters(), "i", grid)) CHECK(i == Approx(5.0).epsilon(1e-9));
    // di0/dV = 1/R, di0/dR = -V/R^2, through the differentiated steps.
    check_sensitivity(name, "V", {"i"}, 1e-6);
    check_sensitivity(name, "R", {"i"}, 1e-6);
  }
  // An input has no known derivative.
  const auto [ok, text] = lower_text("SteadyInput");
  CHECK_FALSE(ok);
  CHECK(text.find("SteadyInput.mo:11:3: error: der() in an initial equation of a variable that depends on an input") !=
        std::string::npos);
}
