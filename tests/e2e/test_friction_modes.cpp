// Friction written as the MSL's PartialFriction writes it: the mode machine
// (startForward, startBackward, locked, mode) is made of equations outside
// when-clauses that read pre(). Such a Boolean/Integer equation is solved by
// event iteration (an every-event assignment), not as a continuous unknown
// of a Newton block; checked against the exact piecewise solution of an
// inertia driven by A sin(omega t) that sticks, slides and stops.
#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

/// The exact motion: phases that start at rest (w = 0) at time t with angle
/// phi, stuck (dir 0) or sliding forward (+1) or backward (-1).
struct FrictionExact {
  double J, A, omega, tau0, tau0_max;
  struct Phase {
    double t, phi;
    int dir;
  };
  std::vector<Phase> phases;

  [[nodiscard]] double w(const Phase& ph, double t) const {
    if (ph.dir == 0) return 0.0;
    return ((A / omega) * (std::cos(omega * ph.t) - std::cos(omega * t)) - ph.dir * tau0 * (t - ph.t)) / J;
  }
  [[nodiscard]] double phi(const Phase& ph, double t) const {
    if (ph.dir == 0) return ph.phi;
    const double s = t - ph.t;
    return ph.phi + ((A / omega) * std::cos(omega * ph.t) * s -
                     (A / (omega * omega)) * (std::sin(omega * t) - std::sin(omega * ph.t)) -
                     ph.dir * tau0 * s * s / 2) / J;
  }
  /// First t in (from, to] where f changes sign (scan, then bisection), or to.
  template <class F>
  static double first_root(F f, double from, double to) {
    const double h = 1e-3;
    double a = from, fa = f(a);
    for (double b = from + h; b <= to; b += h) {
      const double fb = f(b);
      if ((fa < 0) != (fb < 0)) {
        for (int k = 0; k < 200 && b - a > 1e-14; ++k) {
          const double m = 0.5 * (a + b), fm = f(m);
          ((fa < 0) != (fm < 0) ? b : a) = m;
          if (a == m) fa = fm;
        }
        return b;
      }
      a = b;
      fa = fb;
    }
    return to;
  }
  /// The direction a body at rest at t takes: breaks loose if |A sin| > tau0_max.
  [[nodiscard]] int direction_at(double t) const {
    const double drive = A * std::sin(omega * t);
    return std::fabs(drive) > tau0_max ? (drive > 0 ? 1 : -1) : 0;
  }
  void build(double t_end) {
    phases = {{0.0, 0.0, 0}};
    while (phases.back().t < t_end && phases.size() < 100) {
      const Phase ph = phases.back();
      if (ph.dir == 0) {
        const double t = first_root([&](double s) { return std::fabs(A * std::sin(omega * s)) - tau0_max; },
                                    ph.t + 1e-9, t_end + 1);
        phases.push_back({t, ph.phi, direction_at(t + 1e-12)});
      } else {
        const double t = first_root([&](double s) { return ph.dir * w(ph, s); }, ph.t + 1e-6, t_end + 1);
        phases.push_back({t, phi(ph, t), direction_at(t)});
      }
    }
  }
  [[nodiscard]] const Phase& at(double t) const {
    std::size_t j = 0;
    while (j + 1 < phases.size() && phases[j + 1].t <= t) ++j;
    return phases[j];
  }
};

}  // namespace

TEST_CASE("MSL-style friction mode machine (pre() outside when): stick, slide, stop, exact", "[events][friction]") {
  auto model = compiled_model("e2e_friction_state_machine", {{kData + "FrictionStateMachine.mo", "", {}, true}, {}});
  const auto& info = model->info();
  const auto p = info.default_parameters();
  FrictionExact exact{p[parameter(info, "J")], p[parameter(info, "A")], p[parameter(info, "omega")],
                      p[parameter(info, "tau0")], p[parameter(info, "peak")] * p[parameter(info, "tau0")], {}};
  const double t_end = 10;
  exact.build(t_end);
  std::size_t sliding = 0, stuck = 0;
  for (const auto& ph : exact.phases) (ph.dir == 0 ? stuck : sliding) += ph.t < t_end;
  REQUIRE(sliding >= 3);  // the drive breaks it loose both ways and it sticks again
  REQUIRE(stuck >= 3);
  const auto grid = runtime::OutputGrid::uniform(0, t_end, 1000);
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto phi = column(r.trajectory, "phi"), w = column(r.trajectory, "w");
  double worst = 0;
  for (std::size_t i = 0; i < grid.times.size(); ++i) {
    const double t = grid.times[i];
    const auto& ph = exact.at(t);
    INFO("t = " << t << ", exact phase from " << ph.t << " dir " << ph.dir);
    CHECK(std::fabs(phi[i] - exact.phi(ph, t)) < 1e-6);
    CHECK(std::fabs(w[i] - exact.w(ph, t)) < 1e-6);
    worst = std::max({worst, std::fabs(phi[i] - exact.phi(ph, t)), std::fabs(w[i] - exact.w(ph, t))});
  }
  std::string events;
  for (double e : r.event_times) events += std::to_string(e) + " ";
  INFO("events: " << events);
  for (std::size_t j = 1; j < exact.phases.size(); ++j)
    if (exact.phases[j].t < t_end) {
      INFO("phase change at " << exact.phases[j].t);
      CHECK(std::any_of(r.event_times.begin(), r.event_times.end(),
                        [&](double e) { return std::fabs(e - exact.phases[j].t) < 1e-6; }));
    }
  WARN("friction mode machine: " << exact.phases.size() << " phases, max error " << worst);
}

namespace {

/// The exact motion of ClutchTwoInertias.mo: J1 a1 = T + tau, J2 a2 = -tau,
/// T = A sin(omega t); sliding in direction d (sign of w_rel = w2 - w1) the
/// clutch torque is tau = d tau0, locked both turn together and the clutch
/// carries tau_lock = -J2 T / (J1 + J2) until |tau_lock| > tau0_max.
struct ClutchExact {
  double J1, J2, A, omega, tau0, tau0_max;
  struct Phase {
    double t, phi1, w1, phi2, w2;
    int dir;  ///< 0 locked, else the sliding direction
  };
  struct State {
    double phi1, w1, phi2, w2;
  };
  std::vector<Phase> phases;

  [[nodiscard]] double drive1(double t0, double t) const {  // ∫ T
    return (A / omega) * (std::cos(omega * t0) - std::cos(omega * t));
  }
  [[nodiscard]] double drive2(double t0, double t) const {  // ∫∫ T
    return (A / omega) * std::cos(omega * t0) * (t - t0) -
           (A / (omega * omega)) * (std::sin(omega * t) - std::sin(omega * t0));
  }
  [[nodiscard]] State at(const Phase& ph, double t) const {
    const double s = t - ph.t, i1 = drive1(ph.t, t), i2 = drive2(ph.t, t);
    if (ph.dir == 0) {
      const double J = J1 + J2;
      return {ph.phi1 + ph.w1 * s + i2 / J, ph.w1 + i1 / J, ph.phi2 + ph.w2 * s + i2 / J, ph.w2 + i1 / J};
    }
    const double d = ph.dir;
    return {ph.phi1 + ph.w1 * s + (i2 + d * tau0 * s * s / 2) / J1, ph.w1 + (i1 + d * tau0 * s) / J1,
            ph.phi2 + ph.w2 * s - d * tau0 * s * s / (2 * J2), ph.w2 - d * tau0 * s / J2};
  }
  [[nodiscard]] double tau_lock(double t) const { return -J2 * A * std::sin(omega * t) / (J1 + J2); }
  [[nodiscard]] int direction_at(double t) const {
    const double tl = tau_lock(t);
    return std::fabs(tl) > tau0_max ? (tl > 0 ? 1 : -1) : 0;
  }
  void build(double t_end, double w1_0) {
    phases = {{0.0, 0.0, w1_0, 0.0, 0.0, w1_0 > 0 ? -1 : 1}};
    while (phases.back().t < t_end && phases.size() < 200) {
      const Phase ph = phases.back();
      double t;
      if (ph.dir == 0)
        t = FrictionExact::first_root([&](double s) { return std::fabs(tau_lock(s)) - tau0_max; }, ph.t + 1e-9,
                                      t_end + 1);
      else
        t = FrictionExact::first_root([&](double s) { const State x = at(ph, s); return ph.dir * (x.w2 - x.w1); },
                                      ph.t + 1e-6, t_end + 1);
      const State x = at(ph, t);
      phases.push_back({t, x.phi1, x.w1, x.phi2, x.w2, direction_at(ph.dir == 0 ? t + 1e-12 : t)});
    }
  }
  [[nodiscard]] const Phase& phase(double t) const {
    std::size_t j = 0;
    while (j + 1 < phases.size() && phases[j + 1].t <= t) ++j;
    return phases[j];
  }
};

}  // namespace

// The clutch locks after sliding while the mode machine's first event
// iteration sees an `sa` computed under the sliding hypothesis: with J2
// small that `sa` breaks it loose the other way (startForward, then
// startBackward ...) unless the iteration solves `locked` from the start
// flags before the continuous steps. Before that it stopped at the first
// lock-up with "discrete variables still changing after 50 handler iterations".
TEST_CASE("MSL-style clutch between two inertias: locks after sliding, exact", "[events][friction]") {
  auto model = compiled_model("e2e_clutch_two_inertias", {{kData + "ClutchTwoInertias.mo", "", {}, true}, {}});
  const auto& info = model->info();
  const auto p = info.default_parameters();
  ClutchExact exact{p[parameter(info, "J1")],    p[parameter(info, "J2")],
                    p[parameter(info, "A")],     p[parameter(info, "omega")],
                    p[parameter(info, "tau0")],  p[parameter(info, "peak")] * p[parameter(info, "tau0")],
                    {}};
  const double t_end = 10;
  exact.build(t_end, 2.0);
  std::size_t locks = 0;
  for (std::size_t j = 1; j < exact.phases.size(); ++j) locks += exact.phases[j].dir == 0 && exact.phases[j].t < t_end;
  REQUIRE(locks >= 4);
  const auto grid = runtime::OutputGrid::uniform(0, t_end, 1000);
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto phi1 = column(r.trajectory, "phi1"), w1 = column(r.trajectory, "w1");
  const auto phi2 = column(r.trajectory, "phi2"), w2 = column(r.trajectory, "w2");
  double worst = 0;
  for (std::size_t i = 0; i < grid.times.size(); ++i) {
    const double t = grid.times[i];
    const auto& ph = exact.phase(t);
    const auto x = exact.at(ph, t);
    INFO("t = " << t << ", exact phase from " << ph.t << " dir " << ph.dir);
    const double e = std::max({std::fabs(phi1[i] - x.phi1) / (1 + std::fabs(x.phi1)), std::fabs(w1[i] - x.w1),
                               std::fabs(phi2[i] - x.phi2) / (1 + std::fabs(x.phi2)), std::fabs(w2[i] - x.w2)});
    CHECK(e < 2e-6);
    worst = std::max(worst, e);
  }
  for (std::size_t j = 1; j < exact.phases.size(); ++j)
    if (exact.phases[j].t < t_end) {
      INFO("phase change at " << exact.phases[j].t);
      CHECK(std::any_of(r.event_times.begin(), r.event_times.end(),
                        [&](double e) { return std::fabs(e - exact.phases[j].t) < 1e-6; }));
    }
  WARN("clutch between two inertias: " << exact.phases.size() << " phases (" << locks << " lock-ups), max error "
                                       << worst);
}

TEST_CASE("a mode equation's relation takes its new value at a root where its indicator is exactly 0", "[events][friction]") {
  // The MSL's Rotational Friction example stayed stuck when CVODES returned
  // the breakaway root with sa + tau0_max == 0 exactly: startBackward read
  // sa < -tau0_max from the values, false, and the crossing was lost.
  auto model = compiled_model("e2e_exact_root_relation", {{kData + "ExactRootRelation.mo", "", {}, true}, {}});
  const auto& info = model->info();
  const auto p = info.default_parameters();
  std::vector<double> x(1);
  model->initial_state(p, x);
  REQUIRE(info.num_event_indicators == 1);
  std::vector<double> g(1);
  x = {0.4};
  model->event_indicators(0.4, x, {}, p, g);
  const int up[] = {g[0] < 0 ? 1 : -1};  // x rising through the limit
  x = {0.5};
  model->event_indicators(0.5, x, {}, p, g);
  REQUIRE(g[0] == 0.0);
  auto r = model->handle_event({0.5, up, false}, x, {}, p);
  CHECK(r.discrete_changed);
  CHECK(discrete_value(*model, "over") == 1.0);
  // The event iteration at the same instant (as simulate() runs it): the
  // when-clause on `over` fires once.
  for (int k = 0; k < 5 && r.discrete_changed; ++k) r = model->handle_event({0.5, {}, false}, x, {}, p);
  CHECK_FALSE(r.discrete_changed);
  CHECK(discrete_value(*model, "crossings") == 1.0);
  // Away from a crossing the relation is read from the values, as before.
  model->initial_state(p, x);
  x = {0.5};
  r = model->handle_event({0.5, {}, false}, x, {}, p);
  CHECK(discrete_value(*model, "over") == 0.0);
  // And a whole run counts one crossing, at the limit.
  model->initial_state(p, x);
  const auto run = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, 1, 10), tight());
  REQUIRE(run.ok());
  REQUIRE(run.event_times.size() == 1);
  CHECK(run.event_times[0] == Approx(0.5).epsilon(1e-9));
  CHECK(discrete_value(*model, "crossings") == 1.0);
}

TEST_CASE("a relation whose indicator leaves exactly 0 without a sign change is an event", "[events][friction]") {
  // The MSL's SimpleGearShift: the clutch's fn is 0 until its ramp starts;
  // CVODES takes an indicator that is 0 at a restart as inactive and reports
  // nothing when it leaves 0, so `free = fn <= 0` kept the clutch free.
  auto model = compiled_model("e2e_held_indicator", {{kData + "HeldIndicator.mo", "", {}, true}, {}});
  const auto r = simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 2, 20), "x",
                                        [](double t) { return std::max(0.0, t - 1); }, 1e-8);
  CHECK(discrete_value(*model, "mode") == -1.0);
  REQUIRE(r.event_times.size() == 2);  // on at t = 1, the mode as v leaves 0
  CHECK(r.event_times[0] == Approx(1.0).epsilon(1e-9));
  CHECK(r.event_times[1] == Approx(1.0).epsilon(1e-9));
}

TEST_CASE("a when on an Integer a relation defines fires when the relation crosses", "[events][friction]") {
  // At the root the state is already past the stop, so `stopped` computed
  // from the values was -1 both before and after: the clause never fired
  // and the mass went through the stop (the MSL's Translational Friction).
  auto model = compiled_model("e2e_hard_stop", {{kData + "HardStop.mo", "", {}, true}, {}});
  const double t1 = 2 * (1 - std::sqrt(0.6));
  const auto s = [&](double t) { return t < t1 ? -t + 0.25 * t * t : -0.4 + 0.25 * (t - t1) * (t - t1); };
  const auto r = simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 1, 40), "s", s, 1e-7);
  REQUIRE(r.event_times.size() >= 1);
  CHECK(r.event_times.front() == Approx(t1).margin(1e-8));
}

TEST_CASE("an indicator that leaves a held 0 is no crossing for the values before the event", "[events][friction]") {
  // After each tick time - pulseStart is exactly 0 and then grows: y was
  // true at 0 already, so the count must not rise again (it did, once per
  // tick, when the values before took that relation from the other side).
  auto model = compiled_model("e2e_pulse_count", {{kData + "PulseCount.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  for (const double stop : {0.75, 1.25, 2.75}) {
    const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, stop, 10), tight());
    INFO(r.message);
    REQUIRE(r.ok());
    INFO("t = " << stop);
    CHECK(discrete_value(*model, "count") == std::floor(stop));
  }
}

TEST_CASE("a preferred variable the model never differentiates is a state, so a reinit keeps it", "[events][states]") {
  // Written has v_rel = der(s_rel) only; WithAcceleration also a_rel = der(v_rel),
  // which made s_rel and v_rel states already. Both must choose the same states
  // and give the same trajectories through the bounces off the stop.
  const std::string file = kData + "StopBehindSpring.mo";
  const auto written = lower_spec({{file, "StopBehindSpring.Written", {}, true}, {}});
  std::vector<std::string> states;
  for (const auto& s : written.states) states.push_back(s.info.name);
  std::sort(states.begin(), states.end());
  CHECK(states == std::vector<std::string>{"s2", "s_rel", "v2", "v_rel"});

  auto a = compiled_model("e2e_stop_behind_spring", {{file, "StopBehindSpring.Written", {}, true}, {}});
  auto b = compiled_model("e2e_stop_behind_spring_acc", {{file, "StopBehindSpring.WithAcceleration", {}, true}, {}});
  const auto grid = runtime::OutputGrid::uniform(0, 2, 200);
  const auto ra = runtime::simulate(*a, {}, a->info().default_parameters(), grid, tight());
  const auto rb = runtime::simulate(*b, {}, b->info().default_parameters(), grid, tight());
  INFO(ra.message << " / " << rb.message);
  REQUIRE(ra.ok());
  REQUIRE(rb.ok());
  REQUIRE(ra.event_times.size() >= 2);
  CHECK(ra.event_times.size() == rb.event_times.size());
  for (const char* name : {"s_rel", "v_rel", "s2", "v2"}) {
    const auto x = column(ra.trajectory, name), y = column(rb.trajectory, name);
    for (std::size_t k = 0; k < x.size(); ++k) {
      INFO(name << " at t = " << grid.times[k]);
      CHECK(x[k] == Approx(y[k]).margin(1e-7));
    }
  }
}

TEST_CASE("a preferred variable that cannot be a state leaves the others preferred", "[events][states]") {
  // x depends on time through an if-expression only: it is no state candidate
  // (its derivative would be a dummy), and s_rel, v_rel stay the states.
  const auto m = lower_spec({{kData + "StopBehindSpring.mo", "StopBehindSpring.Unpreferable", {}, true}, {}});
  std::vector<std::string> states;
  for (const auto& s : m.states) states.push_back(s.info.name);
  std::sort(states.begin(), states.end());
  CHECK(states == std::vector<std::string>{"s2", "s_rel", "v2", "v_rel"});
}

TEST_CASE("a when-clause's equations read each other's new values - change() sees another clause's", "[events]") {
  auto model = compiled_model("e2e_table_clauses", {{kData + "TableClauses.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  const std::pair<double, double> expected[] = {{0.5, 0}, {1.5, 10}, {2.5, 20}, {3.5, 30}, {4.5, 40}};
  for (std::size_t k = 0; k < std::size(expected); ++k) {
    const auto [stop, y] = expected[k];
    const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, stop, 10), tight());
    INFO(r.message);
    REQUIRE(r.ok());
    INFO("t = " << stop);
    CHECK(discrete_value(*model, "y") == y);
    CHECK(discrete_value(*model, "count") == static_cast<double>(k));
    CHECK(discrete_value(*model, "nextTime") == (k < 4 ? static_cast<double>(k + 1) : stop - 0.5 + 100));
  }
}
