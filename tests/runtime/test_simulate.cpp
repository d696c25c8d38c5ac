// simulate() against analytic solutions, an independent RK4 reference, and
// analytic event times; solver failures as typed results.
#include "fixtures.hpp"
#include "mo/runtime/simulate.hpp"

#include <catch2/catch.hpp>

#include <numbers>

using namespace mo::runtime;
using namespace mo::runtime::fixtures;

namespace {

Inputs single_input(std::unique_ptr<InputSignal> s) {
  Inputs inputs;
  inputs.add(std::move(s));
  return inputs;
}

// The cart-pendulum written out again with Cramer's rule, independent of the fixture.
std::array<double, 4> cart_pendulum_rhs(double t, const std::array<double, 4>& s) {
  const double m1 = 2, d1 = 15, m2 = 1, d2 = 0.5, l = 0.5, g = 9.81;
  const double force = 3.0 * std::sin(2.0 * std::numbers::pi * t);
  const double phi = s[1], v = s[2], w = s[3];
  const double a11 = m1 + m2, a12 = m2 * l * std::cos(phi) / 2, a22 = m2 * l * l / 3;
  const double b1 = m2 * l * std::sin(phi) * w * w / 2 - d1 * v + force;
  const double b2 = -m2 * g * l * std::sin(phi) / 2 - d2 * w;
  const double det = a11 * a22 - a12 * a12;
  return {v, w, (a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det};
}

// Classical RK4 with n steps per output interval of length dt.
std::vector<std::array<double, 4>> rk4_reference(double dt, std::size_t outputs, std::size_t n) {
  std::vector<std::array<double, 4>> out{{0, 0, 0, 0}};
  std::array<double, 4> s{0, 0, 0, 0};
  double h = dt / static_cast<double>(n), t = 0.0;
  auto axpy = [](const std::array<double, 4>& a, double c, const std::array<double, 4>& b) {
    return std::array<double, 4>{a[0] + c * b[0], a[1] + c * b[1], a[2] + c * b[2], a[3] + c * b[3]};
  };
  for (std::size_t k = 1; k < outputs; ++k) {
    for (std::size_t i = 0; i < n; ++i) {
      auto k1 = cart_pendulum_rhs(t, s);
      auto k2 = cart_pendulum_rhs(t + h / 2, axpy(s, h / 2, k1));
      auto k3 = cart_pendulum_rhs(t + h / 2, axpy(s, h / 2, k2));
      auto k4 = cart_pendulum_rhs(t + h, axpy(s, h, k3));
      for (int j = 0; j < 4; ++j) s[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
      t = static_cast<double>(k - 1) * dt + static_cast<double>(i + 1) * h;
    }
    out.push_back(s);
  }
  return out;
}

SimulationOptions tight() {
  SimulationOptions o;
  o.relative_tolerance = 1e-11;
  o.absolute_tolerance = 1e-13;
  return o;
}

}  // namespace

TEST_CASE("Linear ODE matches its analytic solution", "[simulate]") {
  LinearDecay model;
  const double k = 2.0, a0 = 1.5, u = 0.5;
  std::vector<double> p{k, a0};
  auto result = simulate(model, single_input(constant_input(u)), p, OutputGrid::uniform(0, 3, 30),
                         tight());
  REQUIRE(result.status == SimulationStatus::success);
  REQUIRE(result.trajectory.rows() == 31);
  CHECK(result.trajectory.names() == std::vector<std::string>{"a", "b", "a_out", "kb"});
  for (std::size_t r = 0; r < result.trajectory.rows(); ++r) {
    double t = result.trajectory.times()[r], e = std::exp(-k * t);
    double a = u / k + (a0 - u / k) * e;
    double b = u * t / k + (a0 - u / k) * (1 - e) / k;
    CHECK(result.trajectory.at(r, 0) == Approx(a).margin(1e-9));
    CHECK(result.trajectory.at(r, 1) == Approx(b).margin(1e-9));
    CHECK(result.trajectory.at(r, 3) == Approx(k * b).margin(1e-9));
  }
  CHECK(result.statistics.steps > 0);
  CHECK(result.statistics.rhs_evaluations > 0);
  CHECK(result.statistics.jacobian_evaluations > 0);
  CHECK(result.statistics.events == 0);
}

TEST_CASE("Cart-pendulum under 3 sin(2πt) matches an RK4 reference to 1e-6", "[simulate]") {
  CartPendulum model;
  auto p = model.info().default_parameters();
  const std::size_t intervals = 100;
  auto result = simulate(model, single_input(sine_input(3.0, 1.0)), p,
                         OutputGrid::uniform(0, 10, intervals), tight());
  REQUIRE(result.status == SimulationStatus::success);
  auto reference = rk4_reference(0.1, intervals + 1, 1000);  // h = 1e-4
  double worst = 0.0;
  for (std::size_t r = 0; r <= intervals; ++r)
    for (int j = 0; j < 4; ++j)
      worst = std::max(worst, std::abs(result.trajectory.at(r, j) - reference[r][j]));
  CHECK(worst < 1e-6);
  // The pendulum is actually excited: the comparison is not between zeros.
  double phi_max = 0.0;
  for (double v : result.trajectory.column("phi")) phi_max = std::max(phi_max, std::abs(v));
  CHECK(phi_max > 0.05);
  CHECK(result.trajectory.column("y_phi") == result.trajectory.column("phi"));

  SECTION("the finite-difference Jacobian gives the same trajectory") {
    auto options = tight();
    options.use_model_jacobian = false;
    auto dq = simulate(model, single_input(sine_input(3.0, 1.0)), p,
                       OutputGrid::uniform(0, 10, intervals), options);
    REQUIRE(dq.ok());
    CHECK(dq.statistics.jacobian_evaluations > 0);
    for (std::size_t r = 0; r <= intervals; ++r)
      CHECK(dq.trajectory.at(r, 1) == Approx(result.trajectory.at(r, 1)).margin(1e-7));
  }
}

TEST_CASE("Bouncing ball: event times and reinit match the analytic solution", "[simulate][events]") {
  BouncingBall model;
  const double g = 9.81, e = 0.8, h0 = 1.0;
  std::vector<double> p{g, e, h0};
  auto result = simulate(model, Inputs{}, p, OutputGrid::uniform(0, 3.0, 300), tight());
  REQUIRE(result.status == SimulationStatus::success);
  // t1 = sqrt(2 h0/g); each flight after bounce k lasts 2 e^k v1 / g.
  std::vector<double> expected;
  double v1 = std::sqrt(2 * g * h0), t = std::sqrt(2 * h0 / g), speed = v1;
  while (t < 3.0) {
    expected.push_back(t);
    speed *= e;
    t += 2 * speed / g;
  }
  REQUIRE(result.event_times.size() == expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i)
    CHECK(result.event_times[i] == Approx(expected[i]).margin(1e-7));
  CHECK(result.statistics.events == static_cast<long>(expected.size()));
  CHECK(model.discrete()[0] == static_cast<double>(expected.size()));
  // Between bounces the height is a parabola: check one sample after the second bounce.
  std::size_t row = 150;  // t = 1.5, between the second and third bounce
  double t2 = expected[1], vel = v1 * e * e, tt = result.trajectory.times()[row] - t2;
  REQUIRE(result.trajectory.times()[row] > t2);
  REQUIRE(result.trajectory.times()[row] < expected[2]);
  CHECK(result.trajectory.at(row, 0) == Approx(vel * tt - g * tt * tt / 2).margin(1e-7));
  CHECK(result.trajectory.at(row, 0) >= -1e-9);
}

namespace {

/// A model with one state x named `name`, no input, parameter or output, and
/// an ODE that does not depend on x (empty Jacobians): the frame of the event
/// tests' own models below.
class OneStateModel : public Model {
public:
  explicit OneStateModel(const char* name) {
    info_.name = name;
    info_.states = {state("x", "")};
  }
  const ModelInfo& info() const override { return info_; }
  void outputs(double, std::span<const double>, std::span<const double>,
               std::span<const double>, std::span<double>) override {}
  const Sparsity& jacobian_sparsity(Jacobian block) const override {
    switch (block) {
    case Jacobian::f_x: return sp_f_;
    case Jacobian::f_u: return sp_u_;
    case Jacobian::f_p:
    case Jacobian::x0_p: return sp_p_;
    case Jacobian::h_x: return sp_h_;
    case Jacobian::h_u:
    case Jacobian::h_p: return sp_hu_;
    }
    return sp_f_;
  }
  void jacobian_values(Jacobian, double, std::span<const double>, std::span<const double>,
                       std::span<const double>, std::span<double>) override {}

protected:
  ModelInfo info_;

private:
  Sparsity sp_f_ = Sparsity::empty(1, 1), sp_u_ = Sparsity::empty(1, 0), sp_p_ = Sparsity::empty(1, 0);
  Sparsity sp_h_ = Sparsity::empty(0, 1), sp_hu_ = Sparsity::empty(0, 0);
};

// x' = d; a time event every 0.5 s toggles d between 1 and 0 (d starts at 1).
// The handler's event iteration is exercised by a second discrete variable
// that follows d one iteration later.
class Toggle final : public OneStateModel {
public:
  Toggle() : OneStateModel("Toggle") {
    info_.discrete = {{"d", "", ""}, {"d_copy", "", ""}};
  }
  std::unique_ptr<Model> clone() const override { return std::make_unique<Toggle>(*this); }
  void initial_state(double, std::span<const double>, std::span<const double>, std::span<double> x0) override {
    x0[0] = 0.0;
    d_ = {1.0, 1.0};
  }
  void rhs(double, std::span<const double>, std::span<const double>, std::span<const double>,
           std::span<double> xdot) override {
    xdot[0] = d_[0];
  }
  double next_time_event(double t) const override { return 0.5 * (std::floor(t / 0.5) + 1.0); }
  EventResponse handle_event(const EventCause& cause, std::span<double>, std::span<const double>,
                             std::span<const double>) override {
    auto pre = d_;
    if (cause.time_event) d_[0] = 1.0 - pre[0];
    d_[1] = pre[0];  // d_copy = pre(d): settles one iteration later
    ++handler_calls;
    return {.discrete_changed = d_ != pre};
  }
  std::span<double> discrete() override { return d_; }
  int handler_calls = 0;

private:
  std::array<double, 2> d_{1.0, 1.0};
};

}  // namespace

TEST_CASE("Time events: handler iterates until discrete variables settle", "[simulate][events]") {
  Toggle model;
  auto result = simulate(model, Inputs{}, {}, OutputGrid::uniform(0, 2.2, 22));
  REQUIRE(result.status == SimulationStatus::success);
  CHECK(result.event_times == std::vector<double>{0.5, 1.0, 1.5, 2.0});
  CHECK(model.handler_calls == 4 * 3);  // change d, copy it, confirm nothing changes
  // x rises on [0,0.5), [1,1.5), [2,2.2): x(2.2) = 0.5 + 0.5 + 0.2
  CHECK(result.trajectory.at(22, 0) == Approx(1.2).margin(1e-8));
  CHECK(result.trajectory.at(5, 0) == Approx(0.5).margin(1e-8));   // t = 0.5
  CHECK(result.trajectory.at(7, 0) == Approx(0.5).margin(1e-8));   // t = 0.7, d = 0
}

namespace {

/// x' = 1 with two indicators that fall to 0 at t = 1 and stay there up to
/// rounding that depends on the call (as the quench tests of a switch at
/// rest, computed by a Newton block from the start it is given): from t = 1
/// on, one call gives (0, 1e-30), the next (1e-30, 0), and so on. CVODES
/// then finds at its root that one is 0 and the other becomes 0 just after:
/// a new root at the same time. Nothing is discrete.
class NoisyZero final : public OneStateModel {
public:
  NoisyZero() : OneStateModel("NoisyZero") {
    info_.num_event_indicators = 2;
    info_.indicator_in_rhs = {false, false};
  }
  std::unique_ptr<Model> clone() const override { return std::make_unique<NoisyZero>(*this); }
  void initial_state(double, std::span<const double>, std::span<const double>, std::span<double> x0) override {
    x0[0] = 0.0;
  }
  void rhs(double, std::span<const double>, std::span<const double>, std::span<const double>,
           std::span<double> xdot) override {
    xdot[0] = 1.0;
  }
  void event_indicators(double t, std::span<const double>, std::span<const double>,
                        std::span<const double>, std::span<double> g) override {
    const bool even = calls_++ % 2 == 0;
    g[0] = t < 1.0 ? 1.0 - t : even ? 0.0 : 1e-30;
    g[1] = t < 1.0 ? 1.0 - t : even ? 1e-30 : 0.0;
  }
  EventResponse handle_event(const EventCause&, std::span<double>, std::span<const double>,
                             std::span<const double>) override {
    return {};
  }
  std::span<double> discrete() override { return {}; }

private:
  std::size_t calls_ = 0;
};

}  // namespace

TEST_CASE("An indicator at 0 up to rounding does not hold the integration at its root", "[simulate][events]") {
  NoisyZero model;
  auto result = simulate(model, Inputs{}, {}, OutputGrid::uniform(0, 3, 30));
  INFO(result.message);
  REQUIRE(result.status == SimulationStatus::success);
  CHECK(result.trajectory.at(30, 0) == Approx(3.0).margin(1e-8));
  CHECK(result.event_times.empty());  // nothing changed at the roots
}

TEST_CASE("Input breakpoints restart the integrator at the jump", "[simulate]") {
  LinearDecay model;
  const double k = 1.0;
  std::vector<double> p{k, 0.0};
  auto result = simulate(model, single_input(step_input(1.0, 1.0)), p,
                         OutputGrid::uniform(0, 3, 30), tight());
  REQUIRE(result.ok());
  CHECK(result.statistics.restarts == 1);
  for (std::size_t r = 0; r < result.trajectory.rows(); ++r) {
    double t = result.trajectory.times()[r];
    double a = t < 1.0 ? 0.0 : 1.0 - std::exp(-(t - 1.0));
    CHECK(result.trajectory.at(r, 0) == Approx(a).margin(1e-9));
  }
}

TEST_CASE("Explicit output times, including repeated and sub-step times", "[simulate]") {
  LinearDecay model;
  std::vector<double> p{2.0, 1.0};
  auto result = simulate(model, single_input(constant_input(0.0)), p,
                         OutputGrid::at({0.0, 1e-6, 0.5, 0.5, 2.0}), tight());
  REQUIRE(result.ok());
  REQUIRE(result.trajectory.rows() == 5);
  CHECK(result.trajectory.at(1, 0) == Approx(std::exp(-2e-6)).epsilon(1e-10));
  CHECK(result.trajectory.at(3, 0) == result.trajectory.at(2, 0));
  CHECK(result.trajectory.at(4, 0) == Approx(std::exp(-4.0)).epsilon(1e-8));
}

namespace {
// A model whose right-hand side turns NaN from t = t_break on.
class Breaks final : public Model {
public:
  explicit Breaks(double t_break) : t_break_(t_break) {
    info_.name = "Breaks";
    info_.states = {state("x", "")};
    sp_ = Sparsity::dense(1, 1);
    none_ = Sparsity::empty(1, 0);
    out_ = Sparsity::empty(0, 1);
    out0_ = Sparsity::empty(0, 0);
  }
  const ModelInfo& info() const override { return info_; }
  std::unique_ptr<Model> clone() const override { return std::make_unique<Breaks>(*this); }
  void initial_state(double, std::span<const double>, std::span<const double>, std::span<double> x0) override { x0[0] = 1.0; }
  void rhs(double t, std::span<const double> x, std::span<const double>, std::span<const double>,
           std::span<double> xdot) override {
    xdot[0] = t < t_break_ ? -x[0] : std::nan("");
  }
  void outputs(double, std::span<const double>, std::span<const double>,
               std::span<const double>, std::span<double>) override {}
  const Sparsity& jacobian_sparsity(Jacobian b) const override {
    if (b == Jacobian::f_x) return sp_;
    if (b == Jacobian::h_x) return out_;
    if (b == Jacobian::h_u || b == Jacobian::h_p) return out0_;
    return none_;
  }
  void jacobian_values(Jacobian b, double, std::span<const double>, std::span<const double>,
                       std::span<const double>, std::span<double> v) override {
    if (b == Jacobian::f_x) v[0] = -1.0;
  }

private:
  double t_break_;
  ModelInfo info_;
  Sparsity sp_, none_, out_, out0_;
};
}  // namespace

TEST_CASE("Solver failures become typed results", "[simulate][errors]") {
  SECTION("a right-hand side that is NaN from the start") {
    Breaks model(-1.0);
    auto result = simulate(model, Inputs{}, {}, OutputGrid::uniform(0, 2, 20));
    CHECK(result.status == SimulationStatus::rhs_failure);
    CHECK(result.message.find("CV_FIRST_RHSFUNC_ERR") != std::string::npos);
    CHECK(result.trajectory.rows() == 1);  // x0 only
  }
  SECTION("a right-hand side that turns NaN at t = 1") {
    // Steps before t = 1 keep succeeding with ever smaller h: CVODES runs out of steps.
    Breaks model(1.0);
    SimulationOptions o;
    o.max_steps = 2000;
    auto result = simulate(model, Inputs{}, {}, OutputGrid::uniform(0, 2, 20), o);
    CHECK_FALSE(result.ok());
    CHECK(result.message.find("CVode failed at t = ") != std::string::npos);
    CHECK(result.trajectory.rows() == 10);  // t = 0 .. 0.9 are kept; f(1) is already NaN
  }
  SECTION("too many steps") {
    CartPendulum model;
    auto options = tight();
    options.max_steps = 5;
    auto result = simulate(model, single_input(sine_input(3.0, 1.0)),
                           model.info().default_parameters(), OutputGrid::uniform(0, 10, 1),
                           options);
    CHECK(result.status == SimulationStatus::too_much_work);
    CHECK(result.message.find("CV_TOO_MUCH_WORK") != std::string::npos);
  }
  SECTION("inconsistent problems are rejected before integrating") {
    CartPendulum model;
    auto p = model.info().default_parameters();
    auto r1 = simulate(model, Inputs{}, p, OutputGrid::uniform(0, 1, 10));
    CHECK(r1.status == SimulationStatus::invalid_problem);
    CHECK(r1.message == "0 input signals for 1 model inputs");
    auto r2 = simulate(model, single_input(constant_input(0)), std::vector<double>{1.0},
                       OutputGrid::uniform(0, 1, 10));
    CHECK(r2.status == SimulationStatus::invalid_problem);
    auto r3 = simulate(model, single_input(constant_input(0)), p, OutputGrid::at({1.0, 0.5}));
    CHECK(r3.message == "output times decrease");
    SimulationOptions o;
    o.sensitivities.method = SensitivityMethod::cvodes_analytic;
    auto r4 = simulate(model, single_input(constant_input(0)), p, OutputGrid::uniform(0, 1, 1), o);
    CHECK(r4.status == SimulationStatus::invalid_problem);
    o.sensitivities.method = SensitivityMethod::model_states;
    auto r5 = simulate(model, single_input(constant_input(0)), p, OutputGrid::uniform(0, 1, 1), o);
    CHECK(r5.status == SimulationStatus::success);  // no sensitivity states, none asked: empty J
    o.sensitivities.parameters = {2};
    auto r6 = simulate(model, single_input(constant_input(0)), p, OutputGrid::uniform(0, 1, 1), o);
    CHECK(r6.status == SimulationStatus::invalid_problem);
    CHECK(r6.message == "model has no sensitivity states for parameter m2");
  }
  SECTION("event limit stops Zeno behaviour") {
    BouncingBall model;
    SimulationOptions o;
    o.max_events = 3;
    auto result = simulate(model, Inputs{}, std::vector<double>{9.81, 0.8, 1.0},
                           OutputGrid::uniform(0, 5, 50), o);
    CHECK(result.status == SimulationStatus::event_limit);
  }
}
