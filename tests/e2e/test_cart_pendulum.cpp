// The cart-pendulum from its .mo files through the whole pipeline:
//  * the equation form driven by a runtime input F = 3 sin(2πt), against the
//    mass-matrix right-hand side of cart-pendulum.md integrated here by RK4;
//  * the paper's Fig. 5 check: the component model, flattened by mocompile
//    from MoLib and by Scilab's modelicat, against the equation form.
#include <array>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

constexpr double kPi = 3.141592653589793;

/// Parameters of cart-pendulum.md.
struct Plant {
  double m1 = 2, d1 = 15, m2 = 1, d2 = 0.5, l = 0.5, g = 9.81;
};

/// (x, phi, v, w)' with the 2x2 mass matrix solved by Cramer's rule.
std::array<double, 4> plant_rhs(const Plant& P, const std::array<double, 4>& s, double F) {
  const double phi = s[1], v = s[2], w = s[3];
  const double a11 = P.m1 + P.m2, a12 = P.m2 * P.l * std::cos(phi) / 2, a22 = P.m2 * P.l * P.l / 3;
  const double b1 = P.m2 * P.l * std::sin(phi) * w * w / 2 - P.d1 * v + F;
  const double b2 = -P.m2 * P.g * P.l * std::sin(phi) / 2 - P.d2 * w;
  const double det = a11 * a22 - a12 * a12;
  return {v, w, (b1 * a22 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det};
}

/// Classical RK4 with step h from 0 state; samples every `every` steps.
std::vector<std::array<double, 4>> rk4_reference(double t_end, double h, std::size_t every) {
  const Plant P;
  auto force = [](double t) { return 3 * std::sin(2 * kPi * t); };
  auto f = [&](double t, const std::array<double, 4>& s) { return plant_rhs(P, s, force(t)); };
  auto axpy = [](const std::array<double, 4>& s, double a, const std::array<double, 4>& k) {
    return std::array<double, 4>{s[0] + a * k[0], s[1] + a * k[1], s[2] + a * k[2], s[3] + a * k[3]};
  };
  std::array<double, 4> s{0, 0, 0, 0};
  std::vector<std::array<double, 4>> out{s};
  const auto steps = static_cast<std::size_t>(std::llround(t_end / h));
  for (std::size_t n = 0; n < steps; ++n) {
    const double t = static_cast<double>(n) * h;
    const auto k1 = f(t, s), k2 = f(t + h / 2, axpy(s, h / 2, k1)), k3 = f(t + h / 2, axpy(s, h / 2, k2)),
               k4 = f(t + h, axpy(s, h, k3));
    for (int i = 0; i < 4; ++i) s[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    if ((n + 1) % every == 0) out.push_back(s);
  }
  return out;
}

ModelSpec ode_spec(const std::string& cls) {
  return {{kModelica + "CartPendulum/CartPendulumODE.mo", cls, {}, true}, {}};
}

/// y_x and y_phi of a sine-driven model (no inputs) over 10 s, 100 intervals.
runtime::SimulationResult simulate_sine_model(const std::string& name, const ModelSpec& spec) {
  auto model = compiled_model(name, spec);
  REQUIRE(model->info().inputs.empty());
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(),
                                   runtime::OutputGrid::uniform(0, 10, 100), tight());
  INFO(r.message);
  REQUIRE(r.ok());
  return r;
}

}  // namespace

TEST_CASE("cart-pendulum ODE from its .mo file matches an RK4 reference of the mass-matrix form") {
  auto model = compiled_model("e2e_cart_pendulum_ode", ode_spec("CartPendulumODE"));
  const auto& info = model->info();
  REQUIRE(info.inputs.size() == 1);
  REQUIRE(info.inputs[0].name == "F");
  runtime::Inputs inputs;
  inputs.add(runtime::sine_input(3.0, 1.0));
  const std::size_t intervals = 1000;  // every 0.01 s
  const auto r = runtime::simulate(*model, inputs, info.default_parameters(),
                                   runtime::OutputGrid::uniform(0, 10, intervals), tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const double h = 1e-4;  // RK4 global error ~ h^4 · C, far below the 1e-6 checked
  const auto ref = rk4_reference(10, h, static_cast<std::size_t>(std::llround(0.01 / h)));
  REQUIRE(ref.size() == intervals + 1);
  const std::array<std::string, 4> names{"x", "phi", "v", "w"};
  double worst = 0, largest = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const auto c = column(r.trajectory, names[i]);
    for (std::size_t k = 0; k <= intervals; ++k) {
      INFO(names[i] << " at t = " << r.trajectory.times()[k]);
      CHECK(std::fabs(c[k] - ref[k][i]) < 1e-6);
      worst = std::max(worst, std::fabs(c[k] - ref[k][i]));
      largest = std::max(largest, std::fabs(ref[k][i]));
    }
  }
  WARN("cart-pendulum ODE vs RK4: max |error| = " << worst << " (max |state| = " << largest
                                                   << ", " << r.statistics.steps << " CVODES steps)");
  CHECK(largest > 0.05);  // the test is not comparing zeros
}

TEST_CASE("paper Fig. 5: component cart-pendulum (mocompile and modelicat flat) equals the ODE form") {
  const auto reference = simulate_sine_model("e2e_cart_pendulum_sine", ode_spec("CartPendulumSine"));
  const auto ref_x = column(reference.trajectory, "y_x"), ref_phi = column(reference.trajectory, "y_phi");

  SECTION("CartPendulumSine equals CartPendulumODE driven by the runtime sine input") {
    auto model = compiled_model("e2e_cart_pendulum_ode", ode_spec("CartPendulumODE"));
    runtime::Inputs inputs;
    inputs.add(runtime::sine_input(3.0, 1.0));
    const auto r = runtime::simulate(*model, inputs, model->info().default_parameters(),
                                     runtime::OutputGrid::uniform(0, 10, 100), tight());
    REQUIRE(r.ok());
    CHECK(max_abs_difference(column(r.trajectory, "y_x"), ref_x) < 1e-6);
    CHECK(max_abs_difference(column(r.trajectory, "y_phi"), ref_phi) < 1e-6);
  }
  SECTION("components flattened by mocompile from MoLib") {
    const ModelSpec spec{{kModelica + "CartPendulum/CartPendulumComponents.mo", "CartPendulumComponentsSine",
                          {kModelica + "MoLib.mo"}, true},
                         {}};
    const auto r = simulate_sine_model("e2e_cart_pendulum_components", spec);
    const double ex = max_abs_difference(column(r.trajectory, "y_x"), ref_x);
    const double ephi = max_abs_difference(column(r.trajectory, "y_phi"), ref_phi);
    WARN("MoLib components vs ODE: max |dx| = " << ex << ", max |dphi| = " << ephi);
    CHECK(ex < 1e-6);
    CHECK(ephi < 1e-6);
  }
  SECTION("components flattened by Scilab's modelicat") {
    const ModelSpec spec{{kModelica + "CartPendulum/CartPendulumComponentsSine_flat.mo", "", {}, true}, {}};
    const auto r = simulate_sine_model("e2e_cart_pendulum_components_flat", spec);
    const double ex = max_abs_difference(column(r.trajectory, "y_x"), ref_x);
    const double ephi = max_abs_difference(column(r.trajectory, "y_phi"), ref_phi);
    WARN("modelicat flat components vs ODE: max |dx| = " << ex << ", max |dphi| = " << ephi);
    CHECK(ex < 1e-6);
    CHECK(ephi < 1e-6);
  }
  CHECK(*std::max_element(ref_phi.begin(), ref_phi.end()) > 0.01);
}
