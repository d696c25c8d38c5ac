// When-clauses, pre() and reinit in generated code: the bouncing ball against
// its analytic trajectory, and the handler's edge semantics.
#include <catch2/catch.hpp>

#include <cmath>

#include "codegen/models.hpp"
#include "codegen/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::codegen::test;

namespace {

/// Height of the ball at t: free fall from h0, then flights of 2 e^k v1 / g.
double analytic_height(double t, double g, double e, double h0) {
  const double t1 = std::sqrt(2 * h0 / g), v1 = g * t1;
  if (t <= t1) return h0 - g * t * t / 2;
  double start = t1, speed = e * v1;
  for (;;) {
    const double flight = 2 * speed / g;
    if (t <= start + flight) {
      const double s = t - start;
      return speed * s - g * s * s / 2;
    }
    start += flight;
    speed *= e;
  }
}

}  // namespace

TEST_CASE("bouncing ball: height after several bounces equals the analytic solution") {
  auto model = compiled("bouncing_ball", bouncing_ball);
  const std::vector<double> p{9.81, 0.8, 1.0};
  runtime::SimulationOptions opt;
  opt.relative_tolerance = 1e-10;
  opt.absolute_tolerance = 1e-12;
  const auto grid = runtime::OutputGrid::uniform(0, 2.7, 270);
  const auto result = runtime::simulate(*model, {}, p, grid, opt);
  REQUIRE(result.ok());
  // Impacts at t1, t1 + 2 e v1/g, ...: five by t = 2.7 (t1 = 0.4515, then flights of 0.72, 0.58, 0.46, 0.37 s).
  REQUIRE(result.event_times.size() == 5);
  const double t1 = std::sqrt(2 / 9.81);
  CHECK(result.event_times[0] == Approx(t1).epsilon(1e-8));
  CHECK(result.event_times[1] == Approx(t1 + 2 * 0.8 * 9.81 * t1 / 9.81).epsilon(1e-8));
  const auto height = result.trajectory.column("height");
  const auto bounces = result.trajectory.column("bounce_count");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    INFO("t = " << grid.times[k]);
    CHECK(std::fabs(height[k] - analytic_height(grid.times[k], 9.81, 0.8, 1.0)) < 1e-6);
  }
  CHECK(bounces.back() == 5.0);
  CHECK(model->discrete()[0] == 5.0);
}

TEST_CASE("bouncing ball: a when-clause fires on the downward crossing only") {
  auto model = compiled("bouncing_ball", bouncing_ball);
  const std::vector<double> p{9.81, 0.8, 1.0};
  std::vector<double> x(2);
  model->initial_state(p, x);
  CHECK(x == std::vector<double>{1.0, 0.0});
  CHECK(model->discrete()[0] == 0.0);
  std::vector<double> g(1);
  model->event_indicators(0.0, x, {}, p, g);
  CHECK(g[0] == 1.0);
  // At the impact h ≈ +1e-14 (slightly above): the crossing direction decides.
  x = {1e-14, -4.0};
  const int down[] = {-1};
  auto r = model->handle_event({0.45, down, false}, x, {}, p);
  CHECK(r.states_reinit);
  CHECK(r.discrete_changed);
  CHECK(x[1] == Approx(3.2));
  CHECK(model->discrete()[0] == 1.0);
  // Event iteration at the same instant: no new firing.
  r = model->handle_event({0.45, {}, false}, x, {}, p);
  CHECK_FALSE(r.states_reinit);
  CHECK_FALSE(r.discrete_changed);
  CHECK(model->discrete()[0] == 1.0);
  // Upward crossing: h < 0 becomes false; nothing fires.
  const int up[] = {1};
  r = model->handle_event({0.9, up, false}, x, {}, p);
  CHECK_FALSE(r.states_reinit);
  CHECK(model->discrete()[0] == 1.0);
  // initial_state resets the discrete variables.
  model->initial_state(p, x);
  CHECK(model->discrete()[0] == 0.0);
}
