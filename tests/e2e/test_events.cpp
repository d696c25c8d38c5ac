// Events from .mo files: when/reinit (bouncing ball), when/pre in a library
// block (MoLib's Pulse driving a mass) and a stick-slip friction element with
// a discrete mode, each against its piecewise analytic solution.
#include <algorithm>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

/// The grid t0..t_end (intervals) merged with `extra` times, sorted.
runtime::OutputGrid grid_with(double t_end, std::size_t intervals, std::vector<double> extra) {
  auto times = runtime::OutputGrid::uniform(0, t_end, intervals).times;
  times.insert(times.end(), extra.begin(), extra.end());
  std::sort(times.begin(), times.end());
  return runtime::OutputGrid::at(std::move(times));
}

/// True if some event time lies within tol of t.
bool has_event_near(const std::vector<double>& events, double t, double tol) {
  return std::any_of(events.begin(), events.end(), [&](double e) { return std::fabs(e - t) <= tol; });
}

}  // namespace

TEST_CASE("bouncing ball .mo: impact times and the peak heights e^(2k) h0 after each bounce") {
  auto model = compiled_model("e2e_bouncing_ball", {{kData + "BouncingBall.mo", "", {}, true}, {}});
  const auto& info = model->info();
  auto p = info.default_parameters();
  const double g = 9.81, e = 0.7, h0 = 2.0;
  p[parameter(info, "g")] = g;
  p[parameter(info, "e")] = e;
  p[parameter(info, "h0")] = h0;  // start value h(start = h0) follows the parameter
  // Impact k at t_k; the flight after it lasts 2 e^k v1/g and peaks half-way at e^(2k) h0.
  const double v1 = std::sqrt(2 * g * h0);
  std::vector<double> impacts{v1 / g}, peaks;
  for (int k = 1; k <= 5; ++k) {
    const double flight = 2 * std::pow(e, k) * v1 / g;
    peaks.push_back(impacts.back() + flight / 2);
    impacts.push_back(impacts.back() + flight);
  }
  const double t_end = impacts[5] - 0.01;  // after the fifth impact's flight begins, before the sixth
  const auto grid = grid_with(t_end, 200, peaks);
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  REQUIRE(r.event_times.size() == 5);
  double worst_t = 0, worst_h = 0;
  for (std::size_t k = 0; k < 5; ++k) {
    INFO("impact " << k + 1);
    CHECK(std::fabs(r.event_times[k] - impacts[k]) < 1e-8);
    worst_t = std::max(worst_t, std::fabs(r.event_times[k] - impacts[k]));
  }
  const auto h = column(r.trajectory, "h");
  for (std::size_t k = 0; k < peaks.size(); ++k) {
    const auto row = static_cast<std::size_t>(
        std::find(grid.times.begin(), grid.times.end(), peaks[k]) - grid.times.begin());
    const double expected = std::pow(e, 2.0 * static_cast<double>(k + 1)) * h0;
    INFO("peak after bounce " << k + 1 << " at t = " << peaks[k]);
    CHECK(std::fabs(h[row] - expected) < 1e-6);
    worst_h = std::max(worst_h, std::fabs(h[row] - expected));
  }
  // Never below the floor by more than the root-finding tolerance.
  CHECK(*std::min_element(h.begin(), h.end()) > -1e-6);
  CHECK(discrete_value(*model, "bounces") == 5.0);
  WARN("bouncing ball: max |impact time error| = " << worst_t << " s, max |peak error| = " << worst_h << " m");
}

TEST_CASE("mass driven by MoLib.Blocks.Sources.Pulse: position piecewise exact, pulse edges hit") {
  auto model = compiled_model("e2e_pulse_mass", {{kData + "PulseMass.mo", "", {kModelica + "MoLib.mo"}, true}, {}});
  const auto& info = model->info();
  const auto p = info.default_parameters();
  const double m = p[parameter(info, "m")], A = p[parameter(info, "pulse.amplitude")],
               width = p[parameter(info, "pulse.width")], period = p[parameter(info, "pulse.period")],
               start = p[parameter(info, "pulse.startTime")];
  const double t_end = 4.0;
  std::vector<std::pair<double, double>> on;  // [a_k, b_k)
  std::vector<double> edges;
  for (double a = start; a < t_end; a += period) {
    on.emplace_back(a, a + width * period / 100);
    edges.insert(edges.end(), {a, a + width * period / 100});
  }
  // v(t) = (A/m)·(time spent on by t); x(t) = (A/m) Σ_k ∫_{a_k}^{min(b_k, t)} (t - τ) dτ.
  auto exact_v = [&](double t) {
    double v = 0;
    for (auto [a, b] : on)
      if (a < t) v += std::min(b, t) - a;
    return A / m * v;
  };
  auto exact_x = [&](double t) {
    double x = 0;
    for (auto [a, b] : on)
      if (a < t) x += ((t - a) * (t - a) - (t - std::min(b, t)) * (t - std::min(b, t))) / 2;
    return A / m * x;
  };
  const auto grid = grid_with(t_end, 400, edges);
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto x = column(r.trajectory, "x"), v = column(r.trajectory, "v");
  double worst_x = 0, worst_edge = 0;
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double t = grid.times[k];
    INFO("t = " << t);
    CHECK(std::fabs(x[k] - exact_x(t)) < 1e-6);
    worst_x = std::max(worst_x, std::fabs(x[k] - exact_x(t)));
  }
  // At each edge v is exact only if the force switched at that very time: a
  // switch late or early by dt would leave v off by (A/m)·dt.
  for (double e : edges) {
    const auto k = static_cast<std::size_t>(std::find(grid.times.begin(), grid.times.end(), e) - grid.times.begin());
    INFO("pulse edge at t = " << e);
    CHECK(std::fabs(v[k] - exact_v(e)) < 1e-8);
    worst_edge = std::max(worst_edge, std::fabs(v[k] - exact_v(e)) * m / A);
  }
  // The block's when-clause (next period: T0 := pre(T0) + period) is the
  // simulation's handled event, at every period start after the first.
  std::string events;
  for (double e : r.event_times) events += std::to_string(e) + " ";
  INFO("events: " << events);
  REQUIRE(r.event_times.size() == on.size() - 1);
  for (std::size_t k = 1; k < on.size(); ++k) CHECK(std::fabs(r.event_times[k - 1] - on[k].first) < 1e-9);
  WARN("pulse mass: max |x - exact| = " << worst_x << " m, edges hit within " << worst_edge << " s");
}

TEST_CASE("stick-slip friction: spring-mass with Coulomb friction slides, sticks and breaks away") {
  auto model = compiled_model("e2e_stick_slip", {{kData + "StickSlip.mo", "", {}, true}, {}});
  const auto& info = model->info();
  const auto p = info.default_parameters();
  const double m = p[parameter(info, "m")], k = p[parameter(info, "k")], Fc = p[parameter(info, "Fc")],
               Fs = p[parameter(info, "Fs")], F1 = p[parameter(info, "F1")], tF = p[parameter(info, "tF")],
               x0 = p[parameter(info, "x0")];
  const double w = std::sqrt(k / m), half = std::acos(-1.0) / w;
  // Phases: (start time, start position, mode); sliding phases are half
  // oscillations about c = (F - Fc*mode)/k that end at rest at 2c - x.
  struct Phase {
    double t, x, mode, F;
  };
  std::vector<Phase> phases{{0, x0, -1, 0}};
  const double t_end = 10;
  while (phases.back().t < t_end && phases.size() < 50) {
    Phase ph = phases.back();
    if (ph.mode == 0) {  // stuck: only the force step can break it loose
      if (ph.t >= tF) break;
      const double net = F1 - k * ph.x;
      if (std::fabs(net) <= Fs) break;
      phases.push_back({tF, ph.x, net > 0 ? 1.0 : -1.0, F1});
      continue;
    }
    const double c = (ph.F - Fc * ph.mode) / k, x_end = 2 * c - ph.x, t_stop = ph.t + half;
    REQUIRE((t_stop <= tF || ph.t >= tF));  // no force step inside a sliding phase
    const double net = ph.F - k * x_end;
    phases.push_back({t_stop, x_end, std::fabs(net) <= Fs ? 0.0 : (net > 0 ? 1.0 : -1.0), ph.F});
  }
  REQUIRE(phases.size() >= 7);  // 5 reversals, stuck, breakaway, stuck
  auto exact = [&](double t) {
    std::size_t j = 0;
    while (j + 1 < phases.size() && phases[j + 1].t <= t) ++j;
    const Phase& ph = phases[j];
    if (ph.mode == 0) return ph.x;
    const double c = (ph.F - Fc * ph.mode) / k;
    return c + (ph.x - c) * std::cos(w * (t - ph.t));
  };
  const auto grid = grid_with(t_end, 500, {});
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto x = column(r.trajectory, "x");
  double worst = 0;
  for (std::size_t i = 0; i < grid.times.size(); ++i) {
    INFO("t = " << grid.times[i]);
    CHECK(std::fabs(x[i] - exact(grid.times[i])) < 1e-6);
    worst = std::max(worst, std::fabs(x[i] - exact(grid.times[i])));
  }
  std::string events;
  for (double e : r.event_times) events += std::to_string(e) + " ";
  INFO("events: " << events);
  for (std::size_t j = 1; j < phases.size(); ++j) CHECK(has_event_near(r.event_times, phases[j].t, 1e-7));
  CHECK(discrete_value(*model, "mode") == 0.0);
  CHECK(std::fabs(x.back() - phases.back().x) < 1e-6);
  WARN("stick-slip: " << phases.size() << " phases, final x = " << x.back() << ", max |x - exact| = " << worst);
}

TEST_CASE("an if-equation inside a when-clause assigns each of its variables (WhenIf)", "[events]") {
  auto model = compiled_model("e2e_when_if", {{kData + "WhenIf.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  const std::pair<double, double> expected[] = {{1, 2}, {3, 4}, {5, 6}, {7, 8}, {9, 10}, {11, 10}, {13, 10}};
  for (const auto& [stop, b] : expected) {
    const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, stop, 10), tight());
    INFO(r.message << " at t = " << stop);
    REQUIRE(r.ok());
    CHECK(discrete_value(*model, "b") == Approx(b));
  }
}

TEST_CASE("a when-clause's new value reaches the equations of the same event iteration (ThyristorTimer)") {
  // tests/e2e/data/ThyristorTimer.mo: conducting on [alpha/w, pi/w) of each
  // period, i = v/(R + Ron); blocking, i = Goff v/(1 + R Goff). At the start
  // of a half-wave fire reads the timer before its clause resets it: the
  // thyristor used to latch on there, a sixth of a half-wave early.
  const double f = 50, alpha = M_PI / 6, V = 100, R = 10, Ron = 1e-5, Goff = 1e-5, w = 2 * M_PI * f;
  auto model = compiled_model("e2e_thyristor_timer", {{kData + "ThyristorTimer.mo", "", {}, true}, {}});
  const auto grid = runtime::OutputGrid::uniform(0, 0.06, 240);
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto i = column(r.trajectory, "i");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double t = grid.times[k], v = V * std::sin(w * t);
    const double phase = std::fmod(w * t, 2 * M_PI);
    const bool on = phase > alpha && phase < M_PI;
    INFO("t = " << t);
    CHECK(i[k] == Approx(on ? v / (R + Ron) : Goff * v / (1 + R * Goff)).margin(1e-8));
  }
  // Fired at alpha of each period.
  for (int period = 0; period < 3; ++period) {
    const double fired = (alpha + 2 * M_PI * period) / w;
    CHECK(std::any_of(r.event_times.begin(), r.event_times.end(),
                      [&](double t) { return std::fabs(t - fired) < 1e-9; }));
  }
}

TEST_CASE("a relation whose indicator a clause moves away from zero takes its value again (TwoStepTimers)") {
  // tests/e2e/data/TwoStepTimers.mo: both timers cross zero at t = 1; step
  // B's clause restarts its timer there. The run stopped at the event
  // iteration limit when the crossing's value was held for B's relation too.
  auto model = compiled_model("e2e_two_step_timers", {{kData + "TwoStepTimers.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  for (const double stop : {3.5, 4.5}) {
    const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, stop, 10), tight());
    INFO(r.message);
    REQUIRE(r.ok());
    const bool a_active = stop == 4.5;  // A on [0, 1), [2, 3), [4, 5); B on [1, 2), [3, 4)
    CHECK(discrete_value(*model, "a") == (a_active ? 1.0 : 0.0));
    CHECK(discrete_value(*model, "b") == (a_active ? 0.0 : 1.0));
    CHECK(discrete_value(*model, "entries") == std::floor(stop));
    CHECK(discrete_value(*model, "ta") == (a_active ? 4.0 : 2.0));
    CHECK(discrete_value(*model, "tb") == 3.0);
    for (int k = 1; k <= static_cast<int>(stop); ++k)  // a hand-over at every second
      CHECK(std::any_of(r.event_times.begin(), r.event_times.end(), [&](double t) { return std::fabs(t - k) < 1e-9; }));
  }
}

TEST_CASE("terminate() in a when-clause ends the run at the event, with its message (TerminateWhen)", "[events]") {
  auto model = compiled_model("e2e_terminate_when", {{kData + "TerminateWhen.mo", "", {}, true}, {}});
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(),
                                   runtime::OutputGrid::uniform(0, 2, 200), tight());
  CHECK(r.status == runtime::SimulationStatus::terminated_by_model);
  CHECK(r.ok());
  const double landing = 2 * 4 / 9.81;  // h = v0 t - g t²/2 = 0 again
  CHECK_THAT(r.message, Catch::Contains("terminated by the model at t = "));
  CHECK_THAT(r.message, Catch::EndsWith(": fell back below the start"));
  REQUIRE(r.event_times.size() >= 1);
  CHECK(r.event_times.back() == Approx(landing).margin(1e-8));
  CHECK(r.trajectory.times().back() <= landing + 1e-8);
  CHECK(r.trajectory.times().back() > landing - 0.01 - 1e-9);  // the rows up to the event
  CHECK(discrete_value(*model, "landings") == 1.0);
}

TEST_CASE("a sliding mode ends the run as chattering, naming its indicator (SlidingSwitch)", "[events]") {
  // On this grid CVODES returns the roots (on others its steps straddle them
  // and it stops at max_steps, CV_TOO_MUCH_WORK: also an end, less telling).
  auto model = compiled_model("e2e_sliding_switch", {{kData + "SlidingSwitch.mo", "", {}, true}, {}});
  REQUIRE(model->info().indicator_text.size() == 1);
  CHECK(model->info().indicator_text[0] == "x");
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(),
                                   runtime::OutputGrid::uniform(0, 3, 500), runtime::SimulationOptions{});
  CHECK(r.status == runtime::SimulationStatus::event_limit);
  CHECK_THAT(r.message, Catch::StartsWith("chattering at t = 1.0"));
  CHECK_THAT(r.message, Catch::Contains(": 100000 state events within "));
  CHECK_THAT(r.message, Catch::Contains("100000 of them crossings of event indicator 0, x;"));
  const auto& times = r.trajectory.times();
  REQUIRE(times.size() >= 166);  // the rows up to the sliding
  CHECK(times.back() < 1.01);
  const auto x = column(r.trajectory, "x");
  for (std::size_t k = 0; k < x.size(); ++k) CHECK(x[k] == Approx(std::max(0.0, 1 - times[k])).margin(1e-6));
}

TEST_CASE("relations inside a function generate no events unless asked for (FunctionEvents)", "[events]") {
  auto model = compiled_model("e2e_function_events", {{kData + "FunctionEvents.mo", "", {}, true}, {}});
  const auto& texts = model->info().indicator_text;
  // Event indicators: the Boolean function's, the GenerateEvents one's and
  // the caller's argument's; none of halfWave's or split's sin(w t).
  REQUIRE(texts.size() == 3);
  CHECK(texts[0] == "sin(6.283185307179586*time) - 0.5");
  CHECK(texts[1] == "time - 0.25");
  CHECK(texts[2] == "cos(6.283185307179586*time)");
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(),
                                   runtime::OutputGrid::uniform(0, 2.2, 220), tight());
  INFO(r.message);
  REQUIRE(r.ok());
  for (const double k : {0.0, 1.0, 2.0}) CHECK(has_event_near(r.event_times, k + 1.0 / 12, 1e-8));  // on rises
  for (const double k : {0.0, 1.0}) CHECK(has_event_near(r.event_times, k + 5.0 / 12, 1e-8));       // and falls
  // F(t) = the integral of max(sin(2 pi s), 0) from 0 to t.
  const double pi = 3.141592653589793, w = 2 * pi;
  const auto F = [&](double t) {
    const double k = std::floor(t), rest = t - k;
    return k / pi + (rest < 0.5 ? (1 - std::cos(w * rest)) / w : 2 / w);
  };
  const auto& times = r.trajectory.times();
  const auto x = column(r.trajectory, "x"), xn = column(r.trajectory, "xn");
  const auto xe = column(r.trajectory, "xe"), xl = column(r.trajectory, "xl");
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double t = times[i];
    INFO("t = " << t);
    CHECK(x[i] == Approx(F(t)).margin(1e-6));
    CHECK(xn[i] == Approx((1 - std::cos(w * t)) / w - F(t)).margin(1e-6));
    CHECK(xe[i] == Approx(F(t + 0.25) - F(0.25)).margin(1e-6));
    CHECK(xl[i] == Approx(F(std::max(t, 0.25)) - F(0.25)).margin(1e-6));
  }
  CHECK(discrete_value(*model, "n") == 3.0);  // on at 1/12, 13/12, 25/12
}
