// Lowering flat models to ODE form: the cart-pendulum three ways (equations,
// components flattened by mocompile, components flattened by Scilab's
// modelicat) must give the same 4-state ODE; index reduction on the Cartesian
// pendulum; structural diagnostics.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sys/wait.h>
#include <random>
#include <fmt/format.h>

#include "../frontend/compile.hpp"
#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/lower.hpp"
#include "mo/symbolic/ode_interpreter.hpp"

using namespace mo::symbolic;
using mo::test::compile;
using mo::test::read_file;

namespace {

const std::string kModels = std::string(MO_SOURCE_DIR) + "/modelica/";

struct Lowered {
  std::optional<OdeModel> model;
  std::string diagnostics;
};

/// Parses and flattens `sources`, then lowers class `cls`.
Lowered lower_sources(const std::vector<mo::test::Source>& sources, const std::string& cls) {
  auto c = compile(sources, cls);
  REQUIRE(c.ok());
  mo::frontend::SourceManager sm;
  mo::frontend::DiagnosticEngine diags(sm);
  Lowered out;
  out.model = lower(*c.model, diags);
  for (const auto& d : diags.all()) out.diagnostics += d.message + "\n";
  return out;
}

Lowered lower_file(const std::string& path, const std::string& cls = "") {
  return lower_sources({{path, read_file(path)}}, cls);
}

/// The cart-pendulum of cart-pendulum.md solved for (der v, der w) by hand.
std::array<double, 4> reference_rhs(const std::array<double, 4>& s /* x phi v w */, double F,
                                    double m1 = 2, double d1 = 15, double m2 = 1,
                                    double d2 = 0.5, double l = 0.5, double g = 9.81) {
  const double phi = s[1], v = s[2], w = s[3];
  const double a11 = m1 + m2, a12 = m2 * l * std::cos(phi) / 2, a22 = m2 * l * l / 3;
  const double b1 = m2 * l * std::sin(phi) * w * w / 2 - d1 * v + F;
  const double b2 = -m2 * g * l * std::sin(phi) / 2 - d2 * w;
  const double det = a11 * a22 - a12 * a12;
  return {v, w, (b1 * a22 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det};
}

/// The state named `name`, or the state an eliminated alias `name` equals.
std::optional<std::size_t> state_or_alias(const OdeModel& m, const std::string& name) {
  if (auto i = m.state_index(name)) return i;
  for (const auto& e : m.eliminated)
    if (e.info.name == name)
      for (std::size_t i = 0; i < m.states.size(); ++i)
        if (m.states[i].symbol == e.value) return i;
  return std::nullopt;
}

/// Checks der(x) of `m` against reference_rhs at random points; `names`
/// gives the model's names (states or their aliases) for (x, phi, v, w).
void check_against_reference(const OdeModel& m, const std::array<std::string, 4>& names) {
  REQUIRE(m.states.size() == 4);
  std::array<std::size_t, 4> index{};
  for (std::size_t k = 0; k < 4; ++k) {
    const auto i = state_or_alias(m, names[k]);
    INFO("state " << names[k] << " in\n" << summary(m));
    REQUIRE(i);
    index[k] = *i;
  }
  OdeInterpreter interp(m);
  std::vector<double> p;
  for (const auto& par : m.parameters) p.push_back(par.value);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-3, 3);
  for (int trial = 0; trial < 20; ++trial) {
    const std::array<double, 4> s{U(rng), U(rng), U(rng), U(rng)};
    const double F = U(rng);
    std::vector<double> x(4), u(m.inputs.size(), F);
    for (std::size_t k = 0; k < 4; ++k) x[index[k]] = s[k];
    const auto xdot = interp.rhs(0.3, x, u, p);
    const auto ref = reference_rhs(s, F);
    for (std::size_t k = 0; k < 4; ++k) CHECK(xdot[index[k]] == Approx(ref[k]).epsilon(1e-12).margin(1e-12));
  }
}

}  // namespace

TEST_CASE("the equation-form cart-pendulum lowers to 4 states and a 2x2 linear block") {
  auto r = lower_file(kModels + "CartPendulum/CartPendulumODE.mo", "CartPendulumODE");
  INFO(r.diagnostics);
  REQUIRE(r.model);
  const OdeModel& m = *r.model;
  CHECK(m.parameters.size() == 6);
  CHECK(m.inputs.size() == 1);
  CHECK(m.outputs.size() == 2);
  std::size_t blocks = 0;
  for (const Step& s : m.steps)
    if (const auto* b = std::get_if<EquationBlock>(&s)) {
      ++blocks;
      CHECK(b->linear);
      CHECK(b->unknowns.size() == 2);
    }
  CHECK(blocks == 1);
  check_against_reference(m, {"x", "phi", "v", "w"});
}

TEST_CASE("the component cart-pendulum flattened by mocompile lowers to the same ODE") {
  auto r = lower_sources({{"MoLib.mo", read_file(kModels + "MoLib.mo")},
                          {"CartPendulumComponents.mo",
                           read_file(kModels + "CartPendulum/CartPendulumComponents.mo")}},
                         "CartPendulumComponents");
  INFO(r.diagnostics);
  REQUIRE(r.model);
  check_against_reference(*r.model, {"cart.s", "revolute.phi", "cart.v", "revolute.w"});
}

TEST_CASE("the component cart-pendulum flattened by Scilab's modelicat lowers to the same ODE") {
  auto r = lower_file(kModels + "CartPendulum/CartPendulumComponents_flat.mo");
  INFO(r.diagnostics);
  REQUIRE(r.model);
  check_against_reference(*r.model, {"cart.s", "revolute.phi", "cart.v", "revolute.w"});
}

TEST_CASE("a differentiated variable eliminated through a parameter-scaled alias keeps its start") {
  // modelicat's RCCharge keeps R and C as parameters, so alias elimination can
  // only drop C1.v (C1.v = V - R*i, numeric coefficient) and i becomes the
  // state: its start must make C1.v(0) = 0, i.e. i(0) = V/R.
  auto r = lower_file(std::string(MO_SOURCE_DIR) + "/tests/frontend/data/scilab/RCCharge.flat.mo");
  INFO(r.diagnostics);
  REQUIRE(r.model);
  const OdeModel& m = *r.model;
  REQUIRE(m.states.size() == 1);
  LeafValues v;
  for (const auto& par : m.parameters) v[par.symbol] = par.value;
  v[m.states[0].symbol] = evaluate(m.arena, std::span(&m.states[0].start, 1), v)[0];
  v[m.time] = 0;
  double c1v = std::nan("");
  if (m.states[0].info.name == "C1.v") c1v = v[m.states[0].symbol];
  for (const auto& e : m.eliminated)
    if (e.info.name == "C1.v") c1v = evaluate(m.arena, std::span(&e.value, 1), v)[0];
  CHECK(c1v == Approx(0.0).margin(1e-12));
}

TEST_CASE("the Cartesian pendulum (index 3) lowers to 2 states and keeps its constraint") {
  auto r = lower_file(std::string(MO_TEST_DATA_DIR) + "/golden/CartesianPendulum.mo");
  INFO(r.diagnostics);
  REQUIRE(r.model);
  OdeModel& m = *r.model;
  REQUIRE(m.states.size() == 2);
  OdeInterpreter interp(m);
  std::vector<double> p{1, 1, 9.81};
  std::vector<double> x = interp.initial_state(p);
  // RK4 over 2 s: the dummy-derivative form solves the position constraint
  // exactly at every evaluation, so drift stays at rounding level.
  const double h = 1e-3;
  double worst = 0, energy0 = 0, energy_drift = 0;
  const Expr xs = *m.arena.find_symbol("x"), ys = *m.arena.find_symbol("y");
  const Expr vxs = *m.arena.find_symbol("vx"), vys = *m.arena.find_symbol("vy");
  for (int k = 0; k <= 2000; ++k) {
    interp.rhs(k * h, x, {}, p);
    const double X = interp.value(xs), Y = interp.value(ys);
    const double e = 0.5 * (std::pow(interp.value(vxs), 2) + std::pow(interp.value(vys), 2)) + 9.81 * Y;
    if (k == 0) energy0 = e;
    energy_drift = std::max(energy_drift, std::abs(e - energy0));
    worst = std::max(worst, std::abs(X * X + Y * Y - 1));
    auto f = [&](double t, const std::vector<double>& s) { return interp.rhs(t, s, {}, p); };
    const auto k1 = f(k * h, x);
    std::vector<double> tmp(x.size());
    auto axpy = [&](const std::vector<double>& d, double a) {
      for (std::size_t i = 0; i < x.size(); ++i) tmp[i] = x[i] + a * d[i];
      return tmp;
    };
    const auto k2 = f(k * h + h / 2, axpy(k1, h / 2));
    const auto k3 = f(k * h + h / 2, axpy(k2, h / 2));
    const auto k4 = f(k * h + h, axpy(k3, h));
    for (std::size_t i = 0; i < x.size(); ++i) x[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  }
  CHECK(worst < 1e-10);
  CHECK(energy_drift < 1e-6);
}

TEST_CASE("a structurally singular model names the over- and under-determined parts") {
  auto r = lower_file(std::string(MO_TEST_DATA_DIR) + "/Singular.mo");
  REQUIRE_FALSE(r.model);
  CHECK_THAT(r.diagnostics, Catch::Contains("over-determined"));
  CHECK_THAT(r.diagnostics, Catch::Contains("no equation is left to determine 'y'"));
}

TEST_CASE("index reduction that would differentiate an input is an error") {
  auto r = lower_file(std::string(MO_TEST_DATA_DIR) + "/InputDerivative.mo");
  REQUIRE_FALSE(r.model);
  CHECK_THAT(r.diagnostics, Catch::Contains("inputs cannot be differentiated"));
}

TEST_CASE("golden dumps of every lowering stage") {
  // Each data/golden/NAME.mo (or .flat.mo) has NAME.expected: the stage trace
  // followed by the lowered model. Regenerate with MO_UPDATE_GOLDEN=1.
  const std::string dir = std::string(MO_TEST_DATA_DIR) + "/golden";
  const auto files = mo::test::list_files(dir, ".mo");
  REQUIRE(files.size() >= 5);
  for (const auto& path : files) {
    auto c = compile({{path, read_file(path)}});
    INFO(path << "\n" << c.diagnostics);
    REQUIRE(c.ok());
    mo::frontend::SourceManager sm;
    mo::frontend::DiagnosticEngine diags(sm);
    std::string trace;
    LowerOptions options;
    options.trace = &trace;
    auto m = lower(*c.model, diags, options);
    REQUIRE(m);
    const std::string actual = trace + "== ode ==\n" + print_ode(*m);
    const std::string expected_path = path.substr(0, path.find('.', path.rfind('/'))) + ".expected";
    if (std::getenv("MO_UPDATE_GOLDEN")) mo::test::write_file(expected_path, actual);
    CHECK(actual == read_file(expected_path));
  }
}

TEST_CASE("mocompile reports structural errors at their source lines and exits 1") {
  const std::string cmd = std::string(MO_BINARY_DIR) + "/tools/mocompile " + MO_TEST_DATA_DIR +
                          "/Singular.mo --emit ode 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  REQUIRE(pipe);
  std::string out;
  char buf[512];
  while (std::fgets(buf, sizeof buf, pipe)) out += buf;
  const int status = pclose(pipe);
  INFO(out);
  CHECK(WEXITSTATUS(status) == 1);
  CHECK_THAT(out, Catch::Contains("Singular.mo:8:3: error: structurally singular: this equation"));
  CHECK_THAT(out, Catch::Contains("Singular.mo:5:8: error: structurally singular: no equation is "
                                  "left to determine 'y'"));
}

namespace {

/// Each step reads z twice: written out as a tree, z after 12 steps repeats
/// x 2^12 times. positive(z), a relation on a polynomial of over 100 terms,
/// is used twice: a large shared Boolean.
const char* kDoubling = R"(model Doubling
  function positive
    input Real z;
    output Boolean b;
  protected
    Real s := 0;
  algorithm
    for k in 1:25 loop
      s := s + z^k/k;
    end for;
    b := s > 0.2;
  end positive;
  parameter Real a = 0.9;
  Real x(start = 0.5, fixed = true);
  Real z;
  Real w;
algorithm
  z := x;
  for i in 1:12 loop
    z := a*sin(z) + 0.1*z;
  end for;
  w := if positive(z) then z else -z;
  w := w + (if positive(z) then 1 else 0);
equation
  der(x) = -x + z + 0.01*w;
end Doubling;
)";

/// der(x) of kDoubling computed here.
double doubling_rhs(double x, double a) {
  double z = x, s = 0;
  for (int i = 0; i < 12; ++i) z = a * std::sin(z) + 0.1 * z;
  for (int k = 1; k <= 25; ++k) s += std::pow(z, k) / k;
  const double w = (s > 0.2 ? z : -z) + (s > 0.2 ? 1 : 0);
  return -x + z + 0.01 * w;
}

}  // namespace

TEST_CASE("the printed ODE writes each large shared subexpression once, and reads back the same") {
  const Lowered first = lower_sources({{"Doubling.mo", kDoubling}}, "Doubling");
  REQUIRE(first.model);
  const std::string text = print_ode(*first.model);
  INFO(text);
  CHECK(text.size() < 5000);  // x written out 2^12 times would be over 50 kB
  CHECK_THAT(text, Catch::Contains("Real `$cse1` \"a subexpression the equations share\";"));
  CHECK_THAT(text, Catch::Contains("`$cse1` = "));
  // The printed model is a model: it lowers again (a named Boolean would be
  // an error there) and gives the same derivative as the loop run here.
  const Lowered second = lower_sources({{"Doubling.ode.mo", text}}, "Doubling");
  INFO(second.diagnostics);
  REQUIRE(second.model);
  for (const OdeModel* m : {&*first.model, &*second.model}) {
    REQUIRE(m->states.size() == 1);
    OdeInterpreter interp(*m);
    std::vector<double> p;
    for (const auto& par : m->parameters) p.push_back(par.value);
    for (const double x : {-2.0, -0.3, 0.18, 0.21, 0.5, 1.7}) {
      const std::vector<double> xs{x};
      CHECK(interp.rhs(0, xs, {}, p)[0] == Approx(doubling_rhs(x, 0.9)).epsilon(1e-12).margin(1e-14));
    }
  }
}

TEST_CASE("the printed ODE names the shared parts of a large start value, and reads back the same") {
  // z_k = a sin(z_{k-1}) + 0.1 z_{k-1}, fourteen times: 2^14 copies of `a`
  // written out per start value (the MSL's fullRobot wrote its start angles so,
  // through the kinematic chain, until the text ran out of memory).
  std::string source = "model StartChain\n  parameter Real a = 0.9;\n  parameter Real z0 = a;\n";
  for (int k = 1; k <= 14; ++k)
    source += fmt::format("  parameter Real z{} = a*sin(z{}) + 0.1*z{};\n", k, k - 1, k - 1);
  source += "  Real x(start = z14, fixed = true);\n  Real y(start = 2*z14, fixed = true);\n"
            "equation\n  der(x) = -x;\n  der(y) = -y;\nend StartChain;\n";
  double z = 0.9;
  for (int k = 1; k <= 14; ++k) z = 0.9 * std::sin(z) + 0.1 * z;
  const Lowered first = lower_sources({{"StartChain.mo", source}}, "StartChain");
  REQUIRE(first.model);
  const std::string text = print_ode(*first.model);
  INFO(text);
  CHECK(text.size() < 5000);
  CHECK_THAT(text, Catch::Contains("parameter Real `$cse1` = "));
  const Lowered second = lower_sources({{"StartChain.ode.mo", text}}, "StartChain");
  INFO(second.diagnostics);
  REQUIRE(second.model);
  for (const OdeModel* m : {&*first.model, &*second.model}) {
    LeafValues values;
    for (const auto& p : m->parameters) values[p.symbol] = p.value;
    REQUIRE(m->states.size() == 2);
    CHECK(evaluate(m->arena, std::span(&m->states[0].start, 1), values)[0] == Approx(z).epsilon(1e-14));
    CHECK(evaluate(m->arena, std::span(&m->states[1].start, 1), values)[0] == Approx(2 * z).epsilon(1e-14));
  }
}

TEST_CASE("the printed ODE keeps Boolean and Integer types and when/elsewhen, and reads back to the same text") {
  const std::string source = R"(
model Hysteresis
  Real x(start = 0, fixed = true);
  Boolean on(start = false);
  Integer n(start = 0);
  Integer ticks(start = 0);
  Boolean high = x > 0.3;
  Integer level = if high then 2 else 1;
  Integer whole = integer(2*x);
equation
  der(x) = if on then -1 else 1;
  when x > 0.5 then
    on = true;
  elsewhen x < 0.2 then
    on = false;
  end when;
  when {on, time > 3} then
    n = pre(n) + 1;
  end when;
  when sample(0, 0.5) then
    ticks = pre(ticks) + 1;
  end when;
end Hysteresis;
)";
  const Lowered first = lower_sources({{"Hysteresis.mo", source}}, "Hysteresis");
  REQUIRE(first.model);
  const std::string text = print_ode(*first.model);
  INFO(text);
  // Booleans used to print as `discrete Real on(start = 0)` with `on = 1`,
  // and `b = x > 0.3` then set a number equal to a Boolean: not a model; the
  // elsewhen printed as a second when-clause of `on`, which Modelica's single
  // assignment forbids.
  CHECK_THAT(text, Catch::Contains("discrete Boolean on(start = false);"));
  CHECK_THAT(text, Catch::Contains("discrete Integer n(start = 0);"));
  CHECK_THAT(text, Catch::Contains("discrete Boolean high(start = false);"));
  CHECK_THAT(text, Catch::Contains("  when x > 0.5 then\n    on = true;\n  elsewhen x < 0.2 then\n    on = false;\n  end when;\n"));
  CHECK_THAT(text, Catch::Contains("  when {on, time > 3} then\n    n = pre(n) + 1;\n  end when;\n"));
  CHECK_THAT(text, Catch::Contains("  high = x > 0.3;\n"));
  CHECK_THAT(text, Catch::Contains("  whole = integer(2*x);\n"));  // floor() is Real
  const Lowered second = lower_sources({{"Hysteresis.ode.mo", text}}, "Hysteresis");
  INFO(second.diagnostics);
  REQUIRE(second.model);
  CHECK(print_ode(*second.model) == text);
}

TEST_CASE("elsewhen branches that assign different variables fire on their own, with a warning") {
  // Coselica's friction elements chain mode transitions so; only Scilab's
  // modelicac accepts it (Modelica 3 §8.3.5.2), and fires each branch whose
  // condition becomes true. Branches assigning alike keep Modelica's priority.
  const std::string source = R"(
model Modes
  Real x(start = 0, fixed = true);
  discrete Real a(start = 0);
  discrete Real b(start = 0);
  discrete Real c(start = 0);
equation
  der(x) = 1;
  when x > 0.5 then
    a = 1;
  elsewhen x > 0.7 then
    b = 1;
  end when;
  when x > 0.2 then
    c = 1;
  elsewhen x > 0.3 then
    c = 2;
  end when;
end Modes;
)";
  const Lowered r = lower_sources({{"Modes.mo", source}}, "Modes");
  REQUIRE(r.model);
  const std::string warning = "the branches of this when-equation assign different variables";
  const auto at = r.diagnostics.find(warning);
  CHECK(at != std::string::npos);
  CHECK(r.diagnostics.find(warning, at + 1) == std::string::npos);  // the second chain is Modelica
  REQUIRE(r.model->whens.size() == 4);
  CHECK_FALSE(r.model->whens[0].prioritised);
  CHECK_FALSE(r.model->whens[1].prioritised);
  CHECK(r.model->whens[2].prioritised);
  CHECK(r.model->whens[3].prioritised);
  CHECK(r.model->whens[0].group == r.model->whens[1].group);
}
