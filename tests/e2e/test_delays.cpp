// delay() (MLS 3.7.2.4) end to end on tests/e2e/data/Delays.mo: the history
// the simulator records (runtime/src/delay_lines.cpp), delayed jumps as time
// events, delays in the initial system, delayed sensitivities, and what is
// refused. References: the method of steps, finite differences, and a
// matched line's exact delay.
#include <cmath>
#include <sstream>

#include "e2e/support.hpp"
#include "mo/runtime/optimize.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

ModelSpec spec(const std::string& name, std::vector<std::string> sensitivities = {}) {
  return {{kData + "Delays.mo", "Delays." + name, {}, true}, std::move(sensitivities)};
}

}  // namespace

TEST_CASE("delay(): x' = -x(t - 1) follows the method of steps") {
  auto model = compiled_model("e2e_delay_steps", spec("Steps"));
  REQUIRE(model->info().num_delays == 1);
  const auto exact = [](double t) {
    double x = 1 - t;
    if (t > 1) x += (t - 1) * (t - 1) / 2;
    if (t > 2) x -= (t - 2) * (t - 2) * (t - 2) / 6;
    return x;
  };
  const auto r = simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 3, 30), "x", exact, 1e-8);
  // The start's break reaches the state at t = 1 and 2 (level 1 and 2 events).
  REQUIRE(r.event_times.size() >= 2);
  CHECK(r.event_times[0] == Approx(1.0).margin(1e-12));
  CHECK(r.event_times[1] == Approx(2.0).margin(1e-12));
}

TEST_CASE("delay(): a step of the delayed signal arrives T later as a time event") {
  auto model = compiled_model("e2e_delay_step", spec("DelayedStep"));
  const auto grid = runtime::OutputGrid::uniform(0, 1, 100);
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  bool at_07 = false;
  for (double t : r.event_times) at_07 = at_07 || std::fabs(t - 0.7) < 1e-12;
  CHECK(at_07);
  const auto y = column(r.trajectory, "y"), x = column(r.trajectory, "x");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double t = grid.times[k];
    INFO("t = " << t);
    if (t < 0.7 - 1e-9) CHECK(y[k] == 0.0);
    if (t > 0.7 - 1e-9) CHECK(y[k] == Approx(1.0).margin(1e-12));
    CHECK(x[k] == Approx(std::max(0.0, t - 0.7)).margin(1e-9));
  }
  CHECK(discrete_value(*model, "late") == 1.0);
}

TEST_CASE("delay(): sensitivities are delays of sensitivities (exact, and against finite differences)") {
  SECTION("x' = -k x(t - 0.7): dx/dk = -t, then -t + (t - 0.7)^2") {
    auto model = compiled_model("e2e_delay_linear_k", spec("Linear", {"k"}));
    const auto exact = [](double t) { return t <= 0.7 ? -t : -t + (t - 0.7) * (t - 0.7); };
    simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 1.4, 28), "d(x)/d(k)", exact, 1e-8);
  }
  SECTION("through a state event whose time moves with k, against central differences") {
    auto model = compiled_model("e2e_delay_switch_k", spec("GainSwitch", {"k"}));
    auto plain = compiled_model("e2e_delay_switch", spec("GainSwitch"));
    const auto grid = runtime::OutputGrid::uniform(0, 2, 20);
    const auto p = model->info().default_parameters();
    auto o = tight();  // the sensitivities jump at the event
    o.sensitivities.method = runtime::SensitivityMethod::model_states;
    const auto r = runtime::simulate(*model, {}, p, grid, o);
    INFO(r.message);
    REQUIRE(r.ok());
    const auto fd = richardson_difference(*plain, p, parameter(plain->info(), "k"), 1e-3, grid, "x");
    const Deviation d = deviation_after_t0(column(r.trajectory, "d(x)/d(k)"), fd);
    INFO("worst " << d.worst << " of " << d.scale);
    CHECK(d.scale > 0.5);
    CHECK(d.worst < 1e-5 * d.scale);
  }
  SECTION("nested and summed delays of x and x^2, against central differences") {
    auto model = compiled_model("e2e_delay_feedback_ka", spec("Feedback", {"k", "a"}));
    auto plain = compiled_model("e2e_delay_feedback", spec("Feedback"));
    const auto grid = runtime::OutputGrid::uniform(0, 3, 30);
    const auto p = model->info().default_parameters();
    const auto r = runtime::simulate(*model, {}, p, grid, tight());
    INFO(r.message);
    REQUIRE(r.ok());
    for (const char* name : {"k", "a"}) {
      const auto fd = richardson_difference(*plain, p, parameter(plain->info(), name), 1e-3, grid, "x");
      const auto generated = column(r.trajectory, std::string("d(x)/d(") + name + ")");
      const Deviation d = deviation_after_t0(generated, fd);
      INFO("d(x)/d(" << name << "): worst " << d.worst << " of " << d.scale);
      CHECK(d.scale > 0.5);
      CHECK(d.worst < 1e-5 * d.scale);
    }
  }
}

TEST_CASE("delay(): a delay time that varies reads the history at t - T(t)") {
  auto model = compiled_model("e2e_delay_varying", spec("VaryingTime"));
  const auto exact = [](double t) {
    const double t1 = 10.0 / 9;
    return t <= t1 ? 1 - t : (1 - t1) - (2 * (t - t1) - 0.45 * (t * t - t1 * t1));
  };
  simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 2.3, 23), "x", exact, 1e-8);
}

TEST_CASE("delay(): a delayed Integer read through integer() steps T after the original") {
  auto model = compiled_model("e2e_delay_count", spec("DelayedCount"));
  const auto grid = runtime::OutputGrid::uniform(0, 2, 80);  // 0.025 apart: at and between ticks
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto n = column(r.trajectory, "n"), m = column(r.trajectory, "m");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double t = grid.times[k];
    INFO("t = " << t);
    CHECK(n[k] == std::floor(t / 0.1 + 1e-9));
    CHECK(m[k] == std::max(0.0, std::floor((t - 0.05) / 0.1 + 1e-9)));
  }
}

TEST_CASE("delay(): the MSL's three-bit counter of JK flip-flops counts the clock's falling edges") {
  // Digital.Examples.Counter3: RS latches closed through TransportDelay,
  // delay(Integer(pre(x)), 0.001) read back through integer(). Enable rises
  // at t = 1 (Sources.Set), the clock (period 1) falls at k + 0.5; the count
  // at t = k is k - 1 from t = 2 on, modulo 8, bits q0 q1 q2 as Logic '0' = 3
  // and '1' = 4. No reference .csv in ../shared: the count is the check.
  auto model = msl_compiled_model("e2e_delay_counter3", {{kData + "MslDelays.mo", "Counter3Run", {}, true}, {}});
  if (!model) return;
  REQUIRE(model->info().num_delays > 0);
  for (int k = 2; k <= 10; ++k) {
    // Ends at t = k (grid 0.02 apart: the output times meet the clock's edges).
    const auto r = runtime::simulate(*model, {}, model->info().default_parameters(),
                                     runtime::OutputGrid::uniform(0, k, 50 * static_cast<std::size_t>(k)), {});
    INFO("t = " << k << ": " << r.message);
    REQUIRE(r.ok());
    const int count = (k - 1) % 8;  // q0, q1, q2: each latch RS1.Nor1.y
    CHECK(discrete_value(*model, "Counter.FF1.RS1.Nor1.y") == 3 + (count & 1));
    CHECK(discrete_value(*model, "Counter.FF2.RS1.Nor1.y") == 3 + ((count >> 1) & 1));
    CHECK(discrete_value(*model, "Counter.FF3.RS1.Nor1.y") == 3 + ((count >> 2) & 1));
  }
}

TEST_CASE("delay(): the MSL's FixedDelay and TLine1 delay a sine by their delay time to 1e-6") {
  // Neither model has a state: the steps, and so the history, are the
  // output grid's (0.005 apart).
  const auto grid = runtime::OutputGrid::uniform(0, 1, 200);
  const auto delayed = [](double amplitude) {
    return [amplitude](double t) { return t <= 0.1 ? 0.0 : amplitude * std::sin(4 * M_PI * (t - 0.1)); };
  };
  for (const auto& [cls, amplitude] : {std::pair{"FixedDelayRun", 1.0}, std::pair{"TLineRun", 0.5}}) {
    INFO(cls);
    auto model = msl_compiled_model(std::string("e2e_delay_msl_") + cls, {{kData + "MslDelays.mo", cls, {}, true}, {}});
    if (!model) return;
    const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
    INFO(r.message);
    REQUIRE(r.ok());
    const auto exact = delayed(amplitude);
    const auto values = column(r.trajectory, "y");  // d.y, r2.v
    for (std::size_t k = 0; k < grid.times.size(); ++k) CHECK(values[k] == Approx(exact(grid.times[k])).margin(1e-6));
  }
}

TEST_CASE("delay(): the MSL's VariableDelay reads its input at t - T(t) to 1e-6") {
  auto model = msl_compiled_model("e2e_delay_msl_variable", {{kData + "MslDelays.mo", "VariableDelayRun", {}, true}, {}});
  if (!model) return;
  const auto exact = [](double t) {  // T = 0.1 + 0.1 t (a ramp)
    const double q = t - (0.1 + 0.1 * t);
    return q <= 0 ? 0.0 : std::sin(4 * M_PI * q);
  };
  simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 1, 200), "y", exact, 1e-6);
}

TEST_CASE("delay(): at the start the delayed value is the value itself (a steady start)") {
  auto model = compiled_model("e2e_delay_steady", spec("SteadyStart"));
  simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 2, 20), "x", [](double) { return 0.5; }, 1e-12);
}

TEST_CASE("delay(): a matched lossless line passes half the source TD later") {
  auto model = compiled_model("e2e_delay_line", spec("Line"));
  REQUIRE(model->info().num_delays == 4);
  // No states: the history is as fine as the steps, which the output grid bounds.
  const auto exact = [](double t) { return t <= 0.1 ? 0.0 : std::sin(10 * (t - 0.1)) / 2; };
  simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 1, 200), "v2", exact, 1e-7);
}

TEST_CASE("delay(): what is refused and why") {
  SECTION("a delay time that varies without delayMax, where it is written") {
    frontend::SourceManager sources;
    frontend::DiagnosticEngine diags(sources);
    auto flat = tools::load_flat_model(spec("VaryingWithoutMax").source, sources, diags);
    REQUIRE(flat);
    CHECK_FALSE(tools::lower_model(*flat, diags));
    std::ostringstream printed;
    diags.print(printed);
    CHECK_THAT(printed.str(), Catch::Contains("Delays.mo:126:24: error: delay(): a delay time that varies "
                                              "needs delayMax"));
  }
  SECTION("sensitivities through a varying delay time") {
    auto ode = lower_spec(spec("VaryingTime"));
    std::string error;
    try {
      error = tools::add_named_sensitivities(ode, {"k"});
    } catch (const std::invalid_argument& e) {
      error = e.what();
    }
    CHECK_THAT(error, Catch::Contains("sensitivities through a varying delay time are not supported"));
  }
  SECTION("a delayed jump at a time that moves with the parameter") {
    auto model = compiled_model("e2e_delay_delayed_switch_k", spec("DelayedSwitch", {"k"}));
    auto o = tight();
    o.sensitivities.method = runtime::SensitivityMethod::model_states;
    const auto r = runtime::simulate(*model, {}, model->info().default_parameters(),
                                     runtime::OutputGrid::uniform(0, 2, 20), o);
    CHECK(r.status == runtime::SimulationStatus::invalid_problem);
    CHECK_THAT(r.message, Catch::Contains("a delay() of a value that jumps here, at a time that depends on "
                                          "parameter k"));
  }
  SECTION("a delay time of 0 at the parameters") {
    auto model = compiled_model("e2e_delay_zero", spec("ZeroTime"));
    const auto r = runtime::simulate(*model, {}, model->info().default_parameters(),
                                     runtime::OutputGrid::uniform(0, 1, 10), {});
    CHECK(r.status == runtime::SimulationStatus::invalid_problem);
    CHECK_THAT(r.message, Catch::Contains("delay time that is not positive"));
  }
  SECTION("CVODES' own sensitivities, which would miss the delayed terms") {
    auto plain = compiled_model("e2e_delay_linear", spec("Linear"));
    runtime::SimulationOptions o;
    o.sensitivities.method = runtime::SensitivityMethod::cvodes_analytic;
    o.sensitivities.parameters = {0};
    const auto r = runtime::simulate(*plain, {}, plain->info().default_parameters(),
                                     runtime::OutputGrid::uniform(0, 1, 10), o);
    CHECK(r.status == runtime::SimulationStatus::invalid_problem);
    CHECK_THAT(r.message, Catch::Contains("compiled sensitivity states"));
  }
  SECTION("collocation") {
    auto model = compiled_model("e2e_delay_linear", spec("Linear"));
    runtime::OptimalControlProblem problem;
    problem.free_parameters.push_back({0, {0.1, 10.0}, std::nullopt});
    const auto r = runtime::solve(*model, problem);
    CHECK(r.status == runtime::OptimizationStatus::invalid_problem);
    CHECK_THAT(r.message, Catch::Contains("does not support delays"));
  }
}
