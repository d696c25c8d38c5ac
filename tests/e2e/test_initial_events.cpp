// Initialisation of discrete variables and fixed non-states (issue 12.5):
// an `initial algorithm` on discrete variables (the MSL's Pulse/Trapezoid
// sources), when-clauses on initial() with pre(v) = v.start at t0, and
// fixed = true on variables that are not states; each against its analytic
// solution.
#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

TEST_CASE("initial algorithm of discrete variables: the MSL Pulse started 2.5 periods before t0") {
  auto model = compiled_model("e2e_initial_algorithm_pulse",
                              {{kData + "InitialAlgorithmPulse.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  // count(0) = integer(2.5) = 2, T_start(0) = -0.5: y = 0 on [0, 0.5), 1 on [0.5, 1), ...
  auto exact_x = [](double t) {
    double x = 0;
    for (double a = 0.5; a < t; a += 1.0) x += std::min(t, a + 0.5) - a;
    return x;
  };
  std::vector<double> x0(model->info().states.size());
  model->initial_state(p, x0);
  CHECK(discrete_value(*model, "count") == 2.0);
  CHECK(discrete_value(*model, "T_start") == -0.5);
  const auto grid = runtime::OutputGrid::uniform(0, 2.2, 44);
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto x = column(r.trajectory, "x");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    INFO("t = " << grid.times[k]);
    CHECK(std::fabs(x[k] - exact_x(grid.times[k])) < 1e-6);
  }
  CHECK(discrete_value(*model, "count") == 4.0);  // periods started at t = 0.5 and 1.5
  CHECK(std::fabs(discrete_value(*model, "T_start") - 1.5) < 1e-8);
}

TEST_CASE("when initial() fires at t0 with pre(v) = v.start - other clauses only on their edge") {
  auto model = compiled_model("e2e_when_initial", {{kData + "WhenInitial.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  std::vector<double> x0(model->info().states.size());
  model->initial_state(p, x0);
  CHECK(discrete_value(*model, "d") == 6.0);
  CHECK(discrete_value(*model, "n") == 5.0);
  CHECK(discrete_value(*model, "e") == 5.0);
  const auto grid = runtime::OutputGrid::uniform(0, 1, 10);
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto x = column(r.trajectory, "x");
  for (std::size_t k = 0; k < grid.times.size(); ++k) CHECK(std::fabs(x[k] - 6 * grid.times[k]) < 1e-8);
  CHECK(discrete_value(*model, "e") == 11.0);  // pre(e) + d at t = 0.5
  CHECK(discrete_value(*model, "n") == 5.0);   // initial() fired once
}

TEST_CASE("fixed = true on variables that are not states sets the states' initial values") {
  auto model = compiled_model("e2e_fixed_non_state", {{kData + "FixedNonState.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  const auto grid = runtime::OutputGrid::uniform(0, 0.2, 20);
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto s_rel = column(r.trajectory, "s_rel");
  // The other state: v_rel = der(s_rel) = -v (preferred, so v is the dummy).
  const auto v_rel = column(r.trajectory, "v_rel");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double t = grid.times[k], e = std::exp(-25 * t);
    INFO("t = " << t);
    CHECK(std::fabs(v_rel[k] + 10 * e) < 1e-6);
    CHECK(std::fabs(s_rel[k] - (1.5 - 0.4 * (1 - e))) < 1e-7);
  }
}

TEST_CASE("a flag set by initial() outside when-clauses is false again when the integration starts") {
  auto model = compiled_model("e2e_initial_flag_outside_when",
                              {{kData + "InitialFlagOutsideWhen.mo", "", {}, true}, {}});
  std::vector<double> x0(model->info().states.size());
  model->initial_state(model->info().default_parameters(), x0);
  CHECK(discrete_value(*model, "kick") == 0.0);
  simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 2, 20), "x", [](double t) { return 1 + t; }, 1e-8);
  CHECK(discrete_value(*model, "kick") == 0.0);
}

TEST_CASE("a discrete equation outside when-clauses holds at initialisation: an on-off controller starts on") {
  auto model = compiled_model("e2e_on_off_start", {{kData + "OnOffStart.mo", "", {}, true}, {}});
  std::vector<double> x0(model->info().states.size());
  model->initial_state(model->info().default_parameters(), x0);
  CHECK(discrete_value(*model, "y") == 1.0);
  // up to 26 at t = 6 (the band's top), then down
  simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 7, 70), "T",
                         [](double t) { return t <= 6 ? 20 + t : 26 - (t - 6); }, 1e-7);
}

TEST_CASE("a when-clause that initial() does not enable is inactive at initialisation") {
  auto model = compiled_model("e2e_when_inactive_at_init", {{kData + "WhenInactiveAtInit.mo", "", {}, true}, {}});
  const auto p = model->info().default_parameters();
  std::vector<double> x0(model->info().states.size());
  model->initial_state(p, x0);
  CHECK(discrete_value(*model, "trig") == 0.0);  // change(u) was true during the initialisation only
  CHECK(discrete_value(*model, "n") == 0.0);
  CHECK(discrete_value(*model, "m") == 1.0);     // initial() enables it: once
  const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, 1, 10), tight());
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(discrete_value(*model, "n") == 1.0);  // u falls at t = 0.5
  CHECK(discrete_value(*model, "m") == 2.0);  // and trig is an element of {initial(), trig}
}

TEST_CASE("a when-clause on the edge of a discrete equation's variable fires in the iteration it changes") {
  auto model = compiled_model("e2e_edge_of_discrete", {{kData + "EdgeOfDiscrete.mo", "", {}, true}, {}});
  const auto grid = runtime::OutputGrid::uniform(0, 1, 20);
  simulate_against_exact(*model, grid, "x", [](double t) { return t < 0.5 ? 0.0 : (t - 0.5) * (t - 0.5) / 2; },
                         1e-8);
  CHECK(discrete_value(*model, "tSwitch") == Approx(0.5).margin(1e-12));
  CHECK(discrete_value(*model, "count") == 1.0);
}
