// The generated forward sensitivity system against central finite differences
// of the base right-hand side, for all five cart-pendulum parameters; start
// values that depend on parameters; structural sparsity.
#include <catch2/catch.hpp>

#include <random>

#include "../frontend/compile.hpp"
#include "mo/symbolic/lower.hpp"
#include "mo/symbolic/ode_interpreter.hpp"
#include "mo/symbolic/sensitivities.hpp"

using namespace mo::symbolic;

namespace {

/// Lowers a compiled model; the test fails if either step does.
OdeModel lowered(const mo::test::Compiled& c) {
  REQUIRE(c.ok());
  mo::frontend::SourceManager sm;
  mo::frontend::DiagnosticEngine diags(sm);
  auto m = lower(*c.model, diags);
  REQUIRE(m);
  return std::move(*m);
}

OdeModel lower_text(const std::string& text) { return lowered(mo::test::compile_text(text)); }

OdeModel cart_pendulum() {
  auto text = mo::test::read_file(std::string(MO_SOURCE_DIR) +
                                  "/modelica/CartPendulum/CartPendulumODE.mo");
  return lowered(mo::test::compile({{"CartPendulumODE.mo", text}}, "CartPendulumODE"));
}

std::vector<double> defaults(const OdeModel& m) {
  std::vector<double> p;
  for (const auto& par : m.parameters) p.push_back(par.value);
  return p;
}

}  // namespace

TEST_CASE("cart-pendulum sensitivity right-hand sides equal finite differences (5 parameters)") {
  OdeModel base = cart_pendulum();
  OdeModel aug = cart_pendulum();
  std::vector<std::size_t> params;
  for (const char* name : {"m1", "d1", "m2", "d2", "l"}) params.push_back(*aug.parameter_index(name));
  add_sensitivities(aug, params);
  const std::size_t nx = base.states.size();
  REQUIRE(aug.num_base_states() == nx);
  OdeInterpreter fb(base), fa(aug);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-2, 2);
  const std::vector<double> p0 = defaults(base);
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<double> x(aug.states.size()), u{U(rng)};
    for (double& v : x) v = U(rng);
    const auto xdot = fa.rhs(0.0, x, u, p0);
    for (std::size_t si = nx; si < aug.states.size(); ++si) {
      const auto& sens = *aug.states[si].sensitivity;
      // d/de f(x + e*S_k, p + e*e_k), S_k the sensitivity states of parameter k.
      auto shifted = [&](double e) {
        std::vector<double> xs(x.begin(), x.begin() + static_cast<long>(nx)), p = p0;
        for (std::size_t sj = nx; sj < aug.states.size(); ++sj)
          if (aug.states[sj].sensitivity->parameter == sens.parameter)
            xs[aug.states[sj].sensitivity->state] += e * x[sj];
        p[sens.parameter] += e;
        return fb.rhs(0.0, xs, u, p)[sens.state];
      };
      const double h = 1e-5;
      const double fd = (shifted(h) - shifted(-h)) / (2 * h);
      INFO(aug.states[si].info.name);
      CHECK(xdot[si] == Approx(fd).epsilon(1e-7).margin(1e-7));
    }
  }
  // Outputs y = (x, phi): their sensitivities are the state sensitivities.
  CHECK(aug.outputs.size() == 2 + 2 * 5);
}

TEST_CASE("sensitivities to a parameter that sets a start value start at dx0/dp") {
  OdeModel m = lower_text(R"(
model Decay
  parameter Real x0 = 2;
  parameter Real k = 0.5;
  Real x(start = x0, fixed = true);
  Real y(start = 1, fixed = true);
equation
  der(x) = -k*x;
  der(y) = -y;
end Decay;)");
  add_sensitivities(m, std::vector<std::size_t>{*m.parameter_index("x0"), *m.parameter_index("k")});
  // Only x depends on x0 and k: y gets no sensitivity states (sparsity).
  REQUIRE(m.states.size() == 4);
  CHECK(m.states[2].info.name == "d(x)/d(x0)");
  CHECK(m.states[3].info.name == "d(x)/d(k)");
  OdeInterpreter f(m);
  const auto x0 = f.initial_state(defaults(m));
  CHECK(x0[2] == 1.0);
  CHECK(x0[3] == 0.0);
  const auto xdot = f.rhs(0, std::vector<double>{2, 1, 1, 0.3}, {}, defaults(m));
  CHECK(xdot[2] == Approx(-0.5));           // -k * S_x0
  CHECK(xdot[3] == Approx(-2 - 0.5 * 0.3));  // -x - k * S_k
}

TEST_CASE("add_sensitivities rejects bad parameter lists") {
  OdeModel m = cart_pendulum();
  CHECK_THROWS_AS(add_sensitivities(m, std::vector<std::size_t>{99}), std::invalid_argument);
  CHECK_THROWS_AS(add_sensitivities(m, std::vector<std::size_t>{0, 0}), std::invalid_argument);
}

TEST_CASE("a parameter that acts only at events gets sensitivity states (issue 15)") {
  // e only in a reinit, T only in an event time, hc only in a when-condition:
  // none of them is in the continuous equations, yet each moves the states.
  const std::string text = R"(
    model Ball
      parameter Real g = 9.81, e = 0.8, T = 0.3, hc = 0, unused = 2;
      Real h(start = 1, fixed = true), v(start = 0, fixed = true), w(start = 0, fixed = true);
    equation
      der(h) = v; der(v) = -g; der(w) = 1;
      when h < hc then reinit(v, -e*pre(v)); end when;
      when time > T then reinit(w, 0); end when;
    end Ball;)";
  for (const char* name : {"e", "T", "hc"}) {
    OdeModel m = lower_text(text);
    const std::size_t k = *m.parameter_index(name);
    add_sensitivities(m, std::vector<std::size_t>{k});
    INFO(name);
    CHECK(m.states.size() == 2 * m.num_base_states());
  }
  OdeModel m = lower_text(text);
  add_sensitivities(m, std::vector<std::size_t>{*m.parameter_index("unused")});
  CHECK(m.states.size() == m.num_base_states());  // acts nowhere: structurally zero
  OdeModel only_g = lower_text(text);
  add_sensitivities(only_g, std::vector<std::size_t>{*only_g.parameter_index("g")});
  CHECK(only_g.states.size() == 2 * only_g.num_base_states());  // g moves h, hence the bounce
}

TEST_CASE("a discrete value held from the states gets discrete sensitivities, a mode flag none") {
  // u holds k*x (its derivative along x, k is not zero), w holds u (through
  // another held value, to a fixed point), mode and n are flags whose values
  // do not move with x: structurally zero derivatives.
  const std::string text = R"(
    model Held
      parameter Real k = 2, a = 1, unused = 3;
      Real x(start = 1, fixed = true);
      discrete Real u(start = 0), w(start = 0), mode(start = 0);
      discrete Integer n(start = 0);
    equation
      der(x) = -a*x + u + w;
      when sample(0, 0.1) then
        u = k*x;
        mode = if x > 0.5 then 1 else 2;
        n = pre(n) + 1;
      end when;
      when x < 0.3 then
        w = 2*pre(u);
      end when;
    end Held;)";
  OdeModel m = lower_text(text);
  const std::size_t nd = m.discrete.size();
  const std::size_t ka[] = {*m.parameter_index("k"), *m.parameter_index("a")};
  add_sensitivities(m, ka);
  std::vector<std::string> names;
  for (std::size_t i = nd; i < m.discrete.size(); ++i) {
    const OdeDiscrete& d = m.discrete[i];
    REQUIRE(d.sensitivity);
    CHECK(d.info.name == sensitivity_name(m.discrete[d.sensitivity->discrete].info.name,
                                          m.parameters[d.sensitivity->parameter].info.name));
    names.push_back(d.info.name);
  }
  CHECK(names == std::vector<std::string>{"d(u)/d(k)", "d(w)/d(k)", "d(u)/d(a)", "d(w)/d(a)"});
  // Only a parameter that reaches no event expression gets none.
  OdeModel none = lower_text(text);
  add_sensitivities(none, std::vector<std::size_t>{*none.parameter_index("unused")});
  CHECK(none.discrete.size() == nd);
}
