// sample(start, interval) time events, when-clauses on vectors of conditions
// and `initial equation pre(y) = y_start` (issue 12, the MSL's Blocks.Sources,
// MathInteger and Logical blocks), each against its exact solution.
#include "e2e/cli.hpp"
#include "e2e/event_sensitivity_check.hpp"
#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

#include <sstream>

using namespace mo;
using namespace mo::e2e;

namespace {

/// An event at t, to the last bits: a tick k of sample(start, interval) is at
/// start + k*interval as one product, not a running sum (0.1 added ten times
/// is 0.9999999999999999). Ticks of two samples within rounding of each
/// other (0.75 and 0.05 + 7*0.1 = 0.7500000000000001) are one event.
bool has_time(const std::vector<double>& times, double t) {
  return std::any_of(times.begin(), times.end(), [&](double e) { return std::fabs(e - t) <= 2.5e-16; });
}

/// The diagnostics of lowering class `cls` of InitialPre.mo, which must fail.
std::string lowering_errors(const std::string& cls) {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  auto flat = tools::load_flat_model({kData + "InitialPre.mo", cls, {}, true}, sources, diags);
  REQUIRE(flat);
  CHECK_FALSE(tools::lower_model(*flat, diags));
  std::ostringstream printed;
  diags.print(printed);
  return printed.str();
}

}  // namespace

TEST_CASE("sample(): ticks at exactly start + k*interval, counters, sample-and-hold, edge") {
  auto model = compiled_model("e2e_sample_clock", {{kData + "SampleClock.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  std::vector<double> x0(model->info().states.size());
  model->initial_state(p, x0);
  CHECK(discrete_value(*model, "n") == 1.0);  // the tick at t = 0, right after initialisation
  CHECK(discrete_value(*model, "e") == 1.0);
  const auto grid = runtime::OutputGrid::uniform(0, 1.0, 20);  // t = 0.05 k
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  // y = integral of n, n = k + 1 on [0.1 k, 0.1 (k + 1)).
  const auto y = column(r.trajectory, "y");
  for (std::size_t j = 0; j < grid.times.size(); ++j) {
    const double t = grid.times[j];
    const double k = std::floor(t / 0.1 + 1e-9);
    const double exact = 0.1 * k * (k + 1) / 2 + (k + 1) * (t - 0.1 * k);
    INFO("t = " << t);
    CHECK(std::fabs(y[j] - exact) < 1e-8);
  }
  std::ostringstream events;
  events.precision(17);
  for (double t : r.event_times) events << t << " ";
  INFO("event times: " << events.str());
  for (int k = 1; k <= 10; ++k) CHECK(has_time(r.event_times, k * 0.1));
  for (int k = 0; k <= 9; ++k) CHECK(has_time(r.event_times, 0.05 + k * 0.1));
  double sum = 0;
  for (int k = 0; k < 10; ++k) sum += 0.1;
  const auto& ev = r.event_times;
  CHECK(sum != 1.0);
  CHECK(std::find(ev.begin(), ev.end(), 10 * 0.1) != ev.end());  // exactly 1.0
  CHECK(std::find(ev.begin(), ev.end(), sum) == ev.end());        // not a running sum
  CHECK(discrete_value(*model, "n") == 11.0);  // t = 0, 0.1, ..., 1.0
  CHECK(std::fabs(discrete_value(*model, "xs") - 0.95) < 1e-9);
  CHECK(discrete_value(*model, "m") == 5.0);  // 0.55, 0.65, ..., 0.95
  CHECK(discrete_value(*model, "e") == 5.0);  // 0, 0.25, 0.5, 0.75, 1.0
  CHECK(discrete_value(*model, "b") == 0.0);  // false again after the instant
}

TEST_CASE("sample(): a run that starts at t0 > 0 ticks at t0 only if t0 is a tick") {
  auto model = compiled_model("e2e_sample_clock", {{kData + "SampleClock.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  std::vector<double> x0(model->info().states.size());
  model->initial_state(0.55, {}, p, x0);  // no tick of sample(0, 0.1) at 0.55 (before: the one at t = 0)
  CHECK(discrete_value(*model, "n") == 0.0);
  CHECK(discrete_value(*model, "xs") == 0.0);  // sample(0.05, 0.1) ticks at 0.55: x(t0) = 0
  model->initial_state(0.6, {}, p, x0);
  CHECK(discrete_value(*model, "n") == 1.0);
  const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0.55, 1.0, 9), tight());
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(discrete_value(*model, "n") == 5.0);  // 0.6, 0.7, 0.8, 0.9, 1.0
  CHECK(std::fabs(discrete_value(*model, "xs") - 0.4) < 1e-9);  // x = t - 0.55 at the tick 0.95
  CHECK(discrete_value(*model, "m") == 0.0);  // x stays below 0.52
}

TEST_CASE("sample(): the ticks move with a parameter interval and start - sensitivities through them") {
  auto model = compiled_model("e2e_sample_clock", {{kData + "SampleClock.mo", "", {}, true}, {}});
  auto p = model->info().default_parameters();
  p[parameter(model->info(), "T")] = 0.3;
  const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, 1.0, 4), tight());
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(discrete_value(*model, "n") == 4.0);  // t = 0, 0.3, 0.6, 0.9
  CHECK(has_time(r.event_times, 3 * 0.3));

  // SampleTicks: tick k of sample(t1, T) is at t1 + k T: dτ/dT = k, dτ/dt1 = 1. y integrates
  // the counter n of sample(0, T), so d(y)/d(T) jumps by -k at tick k; the
  // hold xs = x at the ticks of sample(t1, T) has d(xs)/d(p) = dτ/dp (x = t), a
  // discrete sensitivity (CVODES' run is refused). The grid (k/37) keeps more
  // than 1e-3 from every tick.
  const auto run = run_through_events("e2e_sample_ticks_sens", {kData + "SampleTicks.mo", "", {}, true},
                                      {"T", "t1", "a"}, runtime::OutputGrid::uniform(0, 1.0, 37), 1e-10, 1e-4, false);
  const double worst = worst_relative(run, run.generated, 1e-3, 1e-4);
  WARN("SampleTicks: sensitivities to T, t1 and a vs central differences, worst relative difference " << worst);
  CHECK(worst < 1e-4);
  // y(t) = Σ (t - k T) over the ticks k T <= t, so d(y)/d(T) = -Σ k: at t = 36/37,
  // after the ticks k = 0..9, -45; t1 moves no tick of n.
  REQUIRE(run.times[36] == Approx(36.0 / 37.0));
  const auto& s = run.generated[36];
  const auto ticks = compiled_model("e2e_sample_ticks_sens", {{kData + "SampleTicks.mo", "", {}, true}, {}});
  const std::size_t y = *ticks->info().state_index("y");
  CHECK(s(static_cast<Eigen::Index>(y), 0) == Approx(-45.0).margin(1e-6));
  CHECK(s(static_cast<Eigen::Index>(y), 1) == Approx(0.0).margin(1e-9));

  // In SampleClock, sample(t1, T) ticks with sample(0, 0.25) at t = 0.25; moved
  // by T they part, and the two events' jumps are not one: refused there.
  auto with_s = compiled_model("e2e_sample_clock_sT", {{kData + "SampleClock.mo", "", {}, true}, {"T"}});
  auto options = tight();
  options.sensitivities.method = runtime::SensitivityMethod::model_states;
  const auto rs = runtime::simulate(*with_s, {}, with_s->info().default_parameters(),
                                    runtime::OutputGrid::uniform(0, 1.0, 4), options);
  INFO(rs.message);
  CHECK(rs.status == runtime::SimulationStatus::invalid_problem);
  CHECK(rs.message.find("event at t = 0.25: sample() ticks at this time move apart") != std::string::npos);
}

TEST_CASE("when {a, b, c} fires when any element becomes true, once per instant") {
  auto model = compiled_model("e2e_when_vector", {{kData + "WhenVector.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, 1.0, 10), tight());
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(discrete_value(*model, "n") == 2.0);  // t = 0.3 (two elements at once), t = 0.6
  CHECK(std::fabs(discrete_value(*model, "last") - 0.6) < 1e-8);
  CHECK(discrete_value(*model, "m") == 1.0);  // `or` stays true at 0.6
}

TEST_CASE("an elsewhen branch holds only where no earlier branch is activated (WhenElsewhen)", "[events]") {
  // All three when-equations have both branches activated at one instant
  // (t = 0.5, 0.9), or the second's activated while the first's condition
  // stays true (the ticks after t = 0.2). Each clause used to fire alone, the
  // last one winning: k = 2, v = 100. The fourth is Scilab's kind.
  auto model = compiled_model("e2e_when_elsewhen", {{kData + "WhenElsewhen.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, 1.0, 10), tight());
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(discrete_value(*model, "k") == 1.0);
  CHECK(discrete_value(*model, "n") == 13.0);
  CHECK(discrete_value(*model, "v") == 2.0);
  // Branches assigning different variables: each fires (Scilab's rule).
  CHECK(discrete_value(*model, "a") == 1.0);
  CHECK(discrete_value(*model, "b") == 1.0);
}

TEST_CASE("initial equation pre(y) = y_start fixes the value before initialisation") {
  // T is a triangle between 0.2 and 0.8 of slope ±1; from T(0) = 0.5 it
  // first rises (pre(y) = true) or falls (false).
  auto triangle = [](double t, bool up) {
    const double first = 0.3;  // time to reach the first bound
    if (t <= first) return up ? 0.5 + t : 0.5 - t;
    const double s = std::fmod(t - first, 1.2);  // then 0.6 one way, 0.6 back
    const double from = up ? 0.8 : 0.2, dir = up ? -1.0 : 1.0;
    return s <= 0.6 ? from + dir * s : from + dir * (1.2 - s);
  };
  for (const bool up : {true, false}) {
    const std::string cls = up ? "InitialPre" : "InitialPreOff";
    auto model = compiled_model("e2e_" + cls, {{kData + "InitialPre.mo", cls, {}, true}, {}});
    const auto p = model->info().default_parameters();
    const auto grid = runtime::OutputGrid::uniform(0, 3.0, 60);
    const auto r = runtime::simulate(*model, {}, p, grid, tight());
    INFO(cls << ": " << r.message);
    REQUIRE(r.ok());
    const auto T = column(r.trajectory, "T");
    for (std::size_t k = 0; k < grid.times.size(); ++k) {
      INFO("t = " << grid.times[k]);
      CHECK(std::fabs(T[k] - triangle(grid.times[k], up)) < 1e-7);
    }
  }
}

TEST_CASE("a collocation study on a model with sample(): each tick that changes it is a phase boundary") {
  const fs::path dir = scratch("sample_study");
  const Run r = morun(quoted(kData + "SampleStudy.mop") + " -o " + quoted((dir / "out").string()), dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(r.err.find("3 phases (2 time events from t = 0.25 to 0.75)") != std::string::npos);
  const std::string summary = slurp(dir / "out" / "summary.json");
  CHECK(summary.find("\"time_event\": true") != std::string::npos);
  CHECK(summary.find("\"mode_sequence_held\": true") != std::string::npos);
}

TEST_CASE("a held value that reads another clause's held value is refused at the clause") {
  const fs::path dir = scratch("sample_chain");
  const Run r = morun(quoted(kData + "SampledChain.mop") + " -o " + quoted((dir / "out").string()), dir);
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("SampledChain.mop:13:3: error: when sample(0.1, 0.2): u2 := -u1 reads u1, which another "
                   "clause sets") != std::string::npos);
  CHECK(!fs::exists(dir / "out" / "summary.json"));
}

TEST_CASE("sample(): a start that reads a parameter the initial equations compute (Mean)") {
  // tests/e2e/data/PeriodMean.mo from t = 0.3: t0 = 0.3, ticks at 0.3 + k/f,
  // and y the mean of 1 + cos(2 pi t) over the period before the last tick.
  auto model = compiled_model("e2e_period_mean", {{kData + "PeriodMean.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  const double f = 2, start = 0.3;
  const auto mean = [&](double a) {  // over [a, a + 1/f]
    return 1 + f / (2 * M_PI) * (std::sin(2 * M_PI * (a + 1 / f)) - std::sin(2 * M_PI * a));
  };
  // every 0.035 s, no row at a tick (where the row's value depends on rounding)
  const auto grid = runtime::OutputGrid::uniform(start, start + 57 * 0.035, 57);
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  REQUIRE(r.event_times.size() == 3);  // 0.8, 1.3, 1.8
  for (std::size_t k = 0; k < 3; ++k) CHECK(r.event_times[k] == Approx(start + (k + 1) / f).margin(1e-12));
  const auto y = column(r.trajectory, "m");
  for (std::size_t i = 0; i < grid.times.size(); ++i) {
    const double t = grid.times[i];
    const int ticks = static_cast<int>(std::floor((t - start) * f));  // ticks before t
    const double expected = ticks == 0 ? 0.0 : mean(start + (ticks - 1) / f);
    INFO("t = " << t);
    CHECK(y[i] == Approx(expected).margin(1e-8));
  }
}

TEST_CASE("sample(): a tick that a state event meets within rounding is handled once (RectifiedMean)") {
  // tests/e2e/data/RectifiedMean.mo: each half period's mean of |V sin| is
  // 2 V/pi. The state event of v > 0 lands within rounding of every tick; it
  // used to count as a second tick and set the mean to 0 (pre(x) after the
  // reinit) every other half period.
  auto model = compiled_model("e2e_rectified_mean", {{kData + "RectifiedMean.mo", "", {}, true}, {}});
  const auto grid = runtime::OutputGrid::uniform(0, 0.1, 500);
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto m = column(r.trajectory, "m");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    if (grid.times[k] < 0.0105) continue;  // before the first mean (and the row at its tick)
    INFO("t = " << grid.times[k]);
    CHECK(m[k] == Approx(200 / M_PI).margin(1e-6));
  }
}

TEST_CASE("initial equation pre(b) = pre(a) + 1 reads a's value before initialisation") {
  auto model = compiled_model("e2e_initial_pre_chain", {{kData + "InitialPre.mo", "InitialPreChain", {}, true}, {}});
  const auto p = model->info().default_parameters();
  std::vector<double> x0(model->info().states.size());
  model->initial_state(0.0, {}, p, x0);
  CHECK(discrete_value(*model, "b") == 4.0);
  const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, 1.0, 4), tight());
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(discrete_value(*model, "a") == 4.0);
  CHECK(discrete_value(*model, "b") == 8.0);
}

TEST_CASE("an initial equation on a variable that equals pre() values fixes those (StateGraph's InitialStep)") {
  auto model = compiled_model("e2e_initial_step_chain", {{kData + "InitialPre.mo", "InitialStepChain", {}, true}, {}});
  const auto p = model->info().default_parameters();
  std::vector<double> x0(model->info().states.size());
  model->initial_state(0.0, {}, p, x0);
  // active (an alias of localActive) = true; idle = not pre(busy) = false.
  CHECK(discrete_value(*model, "localActive") == 1.0);
  CHECK(discrete_value(*model, "oldActive") == 1.0);
  CHECK(discrete_value(*model, "busy") == 1.0);
  CHECK(discrete_value(*model, "idle") == 0.0);
  const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, 1.0, 4), tight());
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(discrete_value(*model, "localActive") == 0.0);  // go at t = 0.5
  CHECK(discrete_value(*model, "oldActive") == 1.0);
  CHECK(discrete_value(*model, "busy") == 0.0);
  CHECK(discrete_value(*model, "idle") == 1.0);
}

TEST_CASE("initial equation pre(b) = ... reads variables that equations give from parameters") {
  auto model = compiled_model("e2e_initial_pre_from_variables",
                              {{kData + "InitialPre.mo", "InitialPreFromVariables", {}, true}, {}});
  const auto p = model->info().default_parameters();
  const auto grid = runtime::OutputGrid::uniform(0, 0.2, 20);
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto level = column(r.trajectory, "tank.level");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double t = grid.times[k];
    const double expected = t <= 0.07 ? 0.32 - t : 0.25 - 0.1 * (t - 0.07);
    INFO("t = " << t);
    CHECK(level[k] == Approx(expected).margin(1e-7));
  }
}

TEST_CASE("initial equation pre(b) = ... on a value only the initial system gives is reported") {
  const std::string printed = lowering_errors("InitialPreFromUnknown");
  INFO(printed);
  CHECK(printed.find("InitialPre.mo:116:3: error: pre() values in an initial equation must follow from "
                     "parameters, time, variables that equations give from those, and other pre() values "
                     "(no value for 'level')") != std::string::npos);
}

TEST_CASE("initial equations that contradict each other on pre() values are reported") {
  CHECK(lowering_errors("InitialPreContradiction")
            .find("InitialPre.mo:73:3: error: this initial equation contradicts the others on pre() "
                  "values: its sides evaluate to 1 and 0") != std::string::npos);
}
