// Tearing of nonlinear blocks (symbolic/src/tearing.hpp), from .mo text: a
// diode whose thermal voltage depends on its own temperature (data/tearing/).
// Whole, its block cannot start from zero guesses; torn, it runs, and it
// equals the whole block started from good guesses; generated code equals
// the interpreter; Jacobians and sensitivities equal finite differences.
#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "codegen/jacobian_check.hpp"
#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"
#include "mo/symbolic/lower.hpp"
#include "mo/symbolic/ode_interpreter.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

const std::string kTearing = kData + "tearing/";

tools::ModelSource diode() { return {kTearing + "DiodeThermalLoop.mo", "", {}, true}; }
tools::ModelSource diode_started() {
  return {kTearing + "DiodeThermalLoopStarted.mo", "", {kTearing + "DiodeThermalLoop.mo"}, true};
}

symbolic::OdeModel lower_source(const tools::ModelSource& source, bool tearing) {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  std::ostringstream printed;
  auto flat = tools::load_flat_model(source, sources, diags);
  std::optional<symbolic::OdeModel> ode;
  symbolic::LowerOptions options;
  options.tearing = tearing;
  if (flat) ode = symbolic::lower(*flat, diags, options);
  diags.print(printed);
  INFO(printed.str());
  REQUIRE(ode);
  return std::move(*ode);
}

/// Sizes of the nonlinear blocks and the number of assignments.
struct Shape {
  std::vector<std::size_t> nonlinear;
  std::size_t assignments = 0;
};

Shape shape(const symbolic::OdeModel& m) {
  Shape s;
  for (const auto& step : m.steps) {
    if (std::holds_alternative<symbolic::Assignment>(step)) ++s.assignments;
    else if (!std::get<symbolic::EquationBlock>(step).linear)
      s.nonlinear.push_back(std::get<symbolic::EquationBlock>(step).unknowns.size());
  }
  return s;
}

const runtime::OutputGrid& grid() {
  static const runtime::OutputGrid g = runtime::OutputGrid::uniform(0, 3, 60);
  return g;
}

}  // namespace

TEST_CASE("tearing: the diode's block of six keeps one iteration variable", "[e2e][tearing]") {
  const Shape whole = shape(lower_source(diode(), false));
  REQUIRE(whole.nonlinear.size() == 1);
  CHECK(whole.nonlinear[0] >= 5);  // i v vt Td dT (and Q unless an alias)
  const Shape torn = shape(lower_source(diode(), true));
  CHECK(torn.nonlinear == std::vector<std::size_t>{1});
  CHECK(torn.assignments == whole.assignments + whole.nonlinear[0] - 1);
}

TEST_CASE("tearing: the whole block fails at t = 0 from zero guesses, the torn one runs", "[e2e][tearing]") {
  auto whole = codegen::test::compiled("e2e_tearing_whole", [] { return lower_source(diode(), false); });
  auto torn = codegen::test::compiled("e2e_tearing_torn", [] { return lower_source(diode(), true); });
  const auto p = torn->info().default_parameters();
  const auto failed = runtime::simulate(*whole, runtime::Inputs{}, p, grid(), tight());
  CHECK_FALSE(failed.ok());
  CHECK(whole->last_failure().find("not finite at the start guess") != std::string::npos);
  const auto r = runtime::simulate(*torn, runtime::Inputs{}, p, grid(), tight());
  INFO(r.message);
  REQUIRE(r.ok());

  // The whole block, started from a thermal voltage of 25 mV, is the reference.
  auto started = codegen::test::compiled("e2e_tearing_started", [] { return lower_source(diode_started(), false); });
  const auto ref = runtime::simulate(*started, runtime::Inputs{}, started->info().default_parameters(), grid(), tight());
  INFO(ref.message);
  REQUIRE(ref.ok());
  for (const char* name : {"Tc", "Td", "i"}) {
    const auto a = column(r.trajectory, name), b = column(ref.trajectory, name);
    double scale = 0;
    for (double v : b) scale = std::max(scale, std::fabs(v));
    INFO(name);
    CHECK(max_abs_difference(a, b) < 1e-8 * scale);
  }
  // Not a trivial trajectory: the diode conducts and heats up.
  const auto i = column(r.trajectory, "i");
  CHECK(*std::max_element(i.begin(), i.end()) > 0.1);
  const auto td = column(r.trajectory, "Td"), tc = column(r.trajectory, "Tc");
  CHECK(max_abs_difference(td, tc) > 0.5);
}

TEST_CASE("tearing: generated code equals the interpreter - Jacobians equal differences", "[e2e][tearing]") {
  const symbolic::OdeModel m = lower_source(diode(), true);
  symbolic::OdeInterpreter interpreter(m);
  auto torn = codegen::test::compiled("e2e_tearing_torn", [] { return lower_source(diode(), true); });
  std::mt19937 rng(10);
  std::uniform_real_distribution<double> t(0, 1), temperature(280, 330);
  const auto p = torn->info().default_parameters();
  for (int k = 0; k < 8; ++k) {
    const double tk = t(rng);
    const std::vector<double> x{temperature(rng)};
    std::vector<double> xdot(1), y(torn->info().outputs.size());
    torn->rhs(tk, x, {}, p, xdot);
    torn->outputs(tk, x, {}, p, y);
    const auto xdot_ref = interpreter.rhs(tk, x, {}, p);
    const auto y_ref = interpreter.outputs(tk, x, {}, p);
    CHECK(xdot[0] == Approx(xdot_ref[0]).epsilon(1e-9).margin(1e-12));
    for (std::size_t j = 0; j < y.size(); ++j) CHECK(y[j] == Approx(y_ref[j]).epsilon(1e-9).margin(1e-12));
    codegen::test::check_jacobians(*torn, tk, x, {}, p, 1e-5);
  }
}

TEST_CASE("tearing: sensitivities through the torn block equal finite differences", "[e2e][tearing]") {
  const std::vector<std::string> names{"G", "R", "n"};
  auto plain = compiled_model("e2e_tearing_plain", {diode(), {}});
  auto augmented = compiled_model("e2e_tearing_sens", {diode(), names});
  const auto& info = augmented->info();
  REQUIRE(info.num_base_states() == 1);
  runtime::SimulationOptions o = tight();
  o.sensitivities.method = runtime::SensitivityMethod::model_states;
  const auto s = runtime::simulate(*augmented, runtime::Inputs{}, info.default_parameters(), grid(), o);
  INFO(s.message);
  REQUIRE(s.ok());
  const auto p = plain->info().default_parameters();
  for (std::size_t j = 0; j < names.size(); ++j) {
    const std::size_t k = parameter(plain->info(), names[j]);
    const double h = 2e-2 * std::fabs(p[k]);  // truncation (h/p)^4, integration noise / h: both ~1e-6
    for (const char* name : {"Tc", "Td"}) {
      const auto fds = richardson_difference(*plain, p, k, h, grid(), name);
      const auto mine = column(s.trajectory, "d(" + std::string(name) + ")/d(" + names[j] + ")");
      const auto [worst, scale] = deviation_after_t0(mine, fds);
      INFO("d(" << name << ")/d(" << names[j] << "): max error " << worst << " of " << scale);
      CHECK(scale > 1e-4);
      // The differences carry the Newton and integrator noise of the runs (about
      // 2e-4 of the case temperature's sensitivity); a sensitivity that missed
      // the torn chain would be off by its whole size.
      CHECK(worst < 1e-3 * scale);
    }
  }
}

TEST_CASE("tearing: a declared start value makes its variable the tearing variable", "[e2e][tearing]") {
  // Without a start value the structure alone chooses x (here der(s)), which
  // starts at 0 where the torn residual's derivative vanishes.
  const symbolic::OdeModel plain = lower_source({kTearing + "NoStartGuess.mo", "", {}, true}, true);
  const symbolic::OdeModel given = lower_source({kTearing + "StartGuessRoot.mo", "", {}, true}, true);
  const auto block_unknown = [](const symbolic::OdeModel& m) {
    for (const auto& step : m.steps)
      if (const auto* b = std::get_if<symbolic::EquationBlock>(&step); b && !b->linear) {
        REQUIRE(b->unknowns.size() == 1);
        return m.arena.symbol_info(b->unknowns[0]).name;
      }
    FAIL("no nonlinear block");
    return std::string();
  };
  CHECK(block_unknown(plain) != "y");
  CHECK(block_unknown(given) == "y");

  // Newton starts from y = -3 and follows the negative root of
  // 2x² + sin(t)·x - (8 + t) = 0 (at t = 0: x = -2, y = -4).
  auto model = compiled_model("e2e_tearing_start_guess", {{kTearing + "StartGuessRoot.mo", "", {}, true}, {}});
  const auto x_exact = [](double t) { return (-std::sin(t) - std::sqrt(std::sin(t) * std::sin(t) + 8 * (8 + t))) / 4; };
  simulate_against_exact(*model, grid(), "x", x_exact, 1e-9);
  simulate_against_exact(*model, grid(), "y", [&](double t) { return 2 * x_exact(t) + std::sin(t); }, 1e-9);
}

TEST_CASE("tearing: springs in series iterate on their joint - a class default start is no guess and explicit tearing variables are dropped", "[e2e][tearing]") {
  // The spring class declares its length with start = 0 (as the MSL's
  // PartialCompliant declares s_rel), the model the joint's position: tearing
  // iterates on the joint, each length follows from it. (Preferring the
  // lengths too made the MSL's ThreeSprings start Newton at lengths 0, where
  // it did not converge.)
  // Without the joint's start, the heuristic tears the lengths first; the
  // joint, torn after them, makes them explicit, and they are dropped.
  const tools::ModelSource source{kTearing + "SeriesSprings.mo", "SeriesSprings.TwoInSeries", {}, true};
  for (const std::string name : {"SeriesSprings.TwoInSeries", "SeriesSprings.TwoInSeriesUnguessed"}) {
    const symbolic::OdeModel m = lower_source({kTearing + "SeriesSprings.mo", name, {}, true}, true);
    std::vector<std::string> iterated;
    for (const auto& step : m.steps)
      if (const auto* b = std::get_if<symbolic::EquationBlock>(&step); b && !b->linear)
        for (const symbolic::Expr u : b->unknowns) iterated.push_back(m.arena.symbol_info(u).name);
    INFO(name << ": " << fmt::format("{}", fmt::join(iterated, ", ")));
    REQUIRE(iterated.size() == 2);
    for (const std::string& v : iterated) CHECK(v.find(".s") == std::string::npos);
  }

  // The pair pulls the mass like one spring of c1 c2/(c1 + c2), rest length L1 + L2.
  auto series = compiled_model("e2e_tearing_series_springs", {source, {}});
  auto single = compiled_model("e2e_tearing_equivalent_spring",
                               {{kTearing + "SeriesSprings.mo", "SeriesSprings.EquivalentSpring", {}, true}, {}});
  const auto g = runtime::OutputGrid::uniform(0, 5, 100);
  const auto a = runtime::simulate(*series, {}, series->info().default_parameters(), g, tight());
  const auto b = runtime::simulate(*single, {}, single->info().default_parameters(), g, tight());
  INFO(a.message << b.message);
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  for (const std::string name : {"b[1]", "b[2]"}) {
    INFO(name);
    CHECK(max_abs_difference(column(a.trajectory, name), column(b.trajectory, name)) < 1e-7);
  }
}

TEST_CASE("tearing: a one-unknown block Newton cycles on is solved by bracketing", "[e2e][tearing]") {
  // Newton from the last solution jumps between the limiter's flat pieces
  // (without the bracketing fallback the run stops at t = 0.0005).
  auto model = compiled_model("e2e_tearing_limiter_loop", {{kTearing + "LimiterLoop.mo", "", {}, true}, {}});
  const double V0 = 15000, A = 1.001;
  const auto vout = [&](double t) {
    return std::clamp(V0 * 20 * std::sin(2 * 3.141592653589793 * 1000 * t) / (1 + V0 / A), -15.0, 15.0);
  };
  const auto r = simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 0.002, 200), "vout", vout, 1e-9);
  CHECK(r.trajectory.times().back() == Approx(0.002));
}

TEST_CASE("a hysteresis in a nonlinear loop switches where its branch ends (SchmittOscillator)",
          "[e2e][tearing]") {
  // Newton continues in time: an integrator's rejected trial step far ahead,
  // where the trigger has already switched, must not decide the branch at
  // the earlier times it retries. Without that rule the trigger switched at
  // random times (the first at t = 0.00068 instead of 0.00499).
  auto model = compiled_model("e2e_schmitt_oscillator", {{kData + "SchmittOscillator.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  const auto grid = runtime::OutputGrid::uniform(0, 0.1, 20000);
  for (const double rtol : {1e-6, 1e-9}) {
    auto options = tight();
    options.relative_tolerance = rtol;
    options.absolute_tolerance = rtol / 100;
    const auto r = runtime::simulate(*model, {}, p, grid, options);
    INFO("rtol " << rtol << ": " << r.message);
    REQUIRE(r.ok());
    const auto y = column(r.trajectory, "y");
    std::vector<double> switches;
    for (std::size_t k = 1; k < y.size(); ++k)
      if ((y[k - 1] < 0) != (y[k] < 0)) switches.push_back(grid.times[k]);
    const double tau = 0.01, beta = 0.5, V0 = 1000, half = 2 * tau * (beta - 1 / V0);
    REQUIRE(switches.size() == 10);
    for (std::size_t k = 0; k < switches.size(); ++k) {
      INFO("switch " << k);
      CHECK(switches[k] == Approx(half / 2 + k * half).margin(1e-5));  // the output grid's spacing: 5e-6
    }
  }
}
