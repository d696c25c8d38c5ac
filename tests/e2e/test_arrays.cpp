// Array forms through the whole pipeline: the models of
// tests/frontend/data/arrays/ (whose flat text the frontend suite pins)
// simulated and compared with their analytic solutions.
#include <functional>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"
#include "mo/symbolic/ode_interpreter.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

const std::string kArrays = std::string(MO_SOURCE_DIR) + "/tests/frontend/data/arrays/";

/// A variable of the model and its exact value as a function of time.
struct Exact {
  std::string name;
  std::function<double(double)> value;
};

/// The values of `name` (a state, an algebraic variable or an eliminated
/// one) at every row of `table`, recomputed by the interpreter from the
/// states, the parameters `p` and time (the result file holds the states).
std::vector<double> values_of(const std::string& model_name, const runtime::ResultTable& table,
                              std::span<const double> p, const std::string& name) {
  const symbolic::OdeModel& m = *compiled_entries().at(model_name).lowered;
  symbolic::OdeInterpreter interp(m);
  auto named = [&](const auto& list) {
    return std::find_if(list.begin(), list.end(), [&](const auto& v) { return v.info.name == name; });
  };
  const auto state = named(m.states);
  const auto algebraic = named(m.algebraics);
  const auto eliminated = named(m.eliminated);
  INFO("variable " << name << " of " << model_name);
  REQUIRE((state != m.states.end() || algebraic != m.algebraics.end() || eliminated != m.eliminated.end()));
  std::vector<double> out;
  for (std::size_t k = 0; k < table.rows(); ++k) {
    const double t = table.times()[k];
    std::vector<double> x;
    for (std::size_t i = 0; i < m.states.size(); ++i) x.push_back(table.at(k, i));
    interp.rhs(t, x, {}, p);
    if (state != m.states.end()) {
      out.push_back(x[static_cast<std::size_t>(state - m.states.begin())]);
    } else if (algebraic != m.algebraics.end()) {
      out.push_back(interp.value(algebraic->symbol));
    } else {
      symbolic::LeafValues v;
      v[m.time] = t;
      for (std::size_t i = 0; i < m.states.size(); ++i) {
        v[m.states[i].symbol] = x[i];
        v[m.states[i].derivative] = interp.value(m.states[i].derivative);
      }
      for (std::size_t i = 0; i < m.parameters.size(); ++i) v[m.parameters[i].symbol] = p[i];
      for (const auto& a : m.algebraics) v[a.symbol] = interp.value(a.symbol);
      out.push_back(symbolic::evaluate(m.arena, std::span(&eliminated->value, 1), v)[0]);
    }
  }
  return out;
}

/// Simulates model `file` of data/arrays on [0, t_end] with default
/// parameters and checks every `exact` variable at every output time.
void check_against(const std::string& file, double t_end, const std::vector<Exact>& exact) {
  const std::string name = "e2e_arrays_" + file.substr(0, file.size() - 3);
  auto model = compiled_model(name, {{kArrays + file, "", {}, true}, {}});
  runtime::SimulationOptions options;
  options.relative_tolerance = 1e-10;
  options.absolute_tolerance = 1e-12;
  const auto grid = runtime::OutputGrid::uniform(0, t_end, 100);
  const auto p = model->info().default_parameters();
  const auto r = runtime::simulate(*model, {}, p, grid, options);
  INFO(file << ": " << r.message);
  REQUIRE(r.ok());
  for (const Exact& e : exact) {
    const auto got = values_of(name, r.trajectory, p, e.name);
    double worst = 0;
    for (std::size_t k = 0; k < grid.times.size(); ++k)
      worst = std::max(worst, std::fabs(got[k] - e.value(grid.times[k])));
    INFO(file << ": " << e.name);
    CHECK(worst < 1e-6);
  }
}

double ex(double rate, double t) { return std::exp(-rate * t); }

}  // namespace

TEST_CASE("array equations (repro: der(x) = -x over an array): x = x0 exp(-k t)", "[arrays]") {
  std::vector<Exact> exact;
  for (int i = 1; i <= 3; ++i) {
    const std::string k = "[" + std::to_string(i) + "]";
    exact.push_back({"x" + k, [i](double t) { return i * ex(0.5, t); }});
    exact.push_back({"y" + k, [i](double t) { return 2 * i * ex(0.5, t); }});
    exact.push_back({"z" + k, [i](double t) { return -2 * i * ex(0.5, t); }});
  }
  check_against("ArrayDecay.mo", 4, exact);
}

TEST_CASE("slices with steps, end and ':' (repro: L[2:3] = L[1:2] + x[2:3])", "[arrays]") {
  auto x = [](int i) { return [i](double t) { return ex(i, t); }; };
  auto s = [](int k) {
    return [k](double t) {
      double sum = 0;
      for (int i = 1; i <= k; ++i) sum += ex(i, t);
      return sum;
    };
  };
  check_against("SliceCascade.mo", 2,
                {{"s[1]", s(1)}, {"s[3]", s(3)}, {"s[5]", s(5)}, {"e[2]", x(3)}, {"e[3]", x(5)},
                 {"c[1]", [](double t) { return 2 * ex(1, t); }}, {"c[2]", [](double t) { return 5 * ex(2, t); }},
                 {"r[3]", [](double t) { return 6 * ex(5, t); }},
                 {"last", [&](double t) { return ex(5, t) + s(4)(t); }}});
}

TEST_CASE("array equations in for- and if-equations, with a time-varying branch", "[arrays]") {
  check_against("ArrayForIf.mo", 2,
                {{"w[2]", [](double t) { return 2 * ex(2, t); }},
                 {"y[3]", [](double t) { return (t < 1 ? 1 : 3) * ex(3, t); }},
                 {"M[2,3]", [](double t) { return 2 * ex(3, t); }}});
}

TEST_CASE("sum, product, min and max over arrays and with iterators", "[arrays]") {
  check_against("ArrayReductions.mo", 2,
                {{"s", [](double t) { return ex(1, t) + ex(2, t) + ex(3, t); }},
                 {"p", [](double t) { return ex(6, t); }},
                 {"lo", [](double t) { return ex(3, t); }},
                 {"hi", [](double t) { return 3 * ex(1, t) + 4 * ex(2, t); }},
                 {"sq", [](double t) { return ex(2, t) + ex(4, t) + ex(6, t); }},
                 {"m2", [](double t) { return 2 * ex(1, t); }}});
}

TEST_CASE("matrix expressions: der(x) = A x with A upper triangular, and every matrix form of x", "[arrays]") {
  // x1 = 2 e^-t - e^-2t, x2 = e^-2t solve der(x) = [-1, 1; 0, -2] x, x(0) = {1, 1}.
  auto x1 = [](double t) { return 2 * ex(1, t) - ex(2, t); };
  auto x2 = [](double t) { return ex(2, t); };
  check_against("MatrixAlgebra.mo", 3,
                {{"x[1]", x1}, {"x[2]", x2},
                 {"Ax[1]", [&](double t) { return -x1(t) + x2(t); }},
                 {"xA[2]", [&](double t) { return x1(t) - 2 * x2(t); }},
                 {"At[1,1]", [](double) { return 0.0; }},
                 {"B[2,4]", x2}, {"B[1,2]", [](double) { return 1.0; }},
                 {"C[3,1]", x1}, {"C[1,2]", [](double) { return 0.0; }},
                 {"E[4,2]", [](double) { return 3.0; }}, {"E[3,1]", x1},
                 {"el[2]", [&](double t) { return 3 * x2(t); }},
                 {"dv[1]", [&](double t) { return x1(t) / 2; }},
                 {"pw[2]", [&](double t) { return x2(t) * x2(t); }},
                 {"ad[1]", [&](double t) { return x1(t) + 1; }},
                 {"sb[2]", [&](double t) { return 1 - x2(t); }},
                 {"op[2,1]", [&](double t) { return 2 * x2(t); }},
                 {"dg[2,2]", [](double) { return 6.0; }}, {"dg[1,2]", [](double) { return 0.0; }},
                 {"ls[2]", [&](double t) { return 0.5 * x1(t); }},
                 {"sc", x1}, {"v[3]", [](double) { return 2.0; }}, {"mt[2,1]", x2},
                 {"nd", [](double) { return 25.0; }},
                 {"sk[1,2]", [](double) { return -1.0; }}, {"sk[3,1]", [&](double t) { return -x2(t); }},
                 {"sy[2,1]", x2},
                 {"q", [&](double t) { return -x1(t) * x1(t) + x1(t) * x2(t) - 2 * x2(t) * x2(t); }}});
}

TEST_CASE("an enumeration type as a dimension, indexed by its literals", "[arrays]") {
  check_against("EnumerationIndexed.mo", 2,
                {{"u[1]", [](double t) { return ex(1, t); }},
                 {"u[3]", [](double t) { return ex(4, t); }},
                 {"fastest", [](double t) { return ex(4, t) - ex(1, t); }}});
}

TEST_CASE("`constraint` as a component name and a UTF-8 byte-order mark simulate", "[arrays]") {
  check_against("ConstraintIdentifier.mo", 2,
                {{"constraint", [](double t) { return 2 * ex(1, t); }},
                 {"y[2]", [](double t) { return 4 * ex(1, t); }},
                 {"z[2]", [](double) { return 2.0; }}});
  check_against("ByteOrderMarked.mo", 2, {{"x", [](double t) { return 3 * ex(2, t); }}});
}

TEST_CASE("a package's constant table indexed by two signals, a row of one, Integer() of an enumeration") {
  auto model = compiled_model("e2e_logic_tables", {{kData + "LogicTables.mo", "LogicTables.Gate", {}, true}, {}});
  const auto p = model->info().default_parameters();
  // (stop time, y = AndTable[a, b]): low, low, unknown, high (ordinals 1, 1, 3, 2).
  for (const auto& [stop, y] : std::vector<std::pair<double, double>>{{0.2, 1}, {0.4, 1}, {0.6, 3}, {0.9, 2}}) {
    const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, stop, 4), tight());
    INFO(r.message << " at " << stop);
    REQUIRE(r.ok());
    CHECK(discrete_value(*model, "y") == y);
  }
  const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, 1, 4), tight());
  REQUIRE(r.ok());
  // x = integral of Integer(y): 1 on [0, 0.5), 3 on [0.5, 0.75), 2 on [0.75, 1].
  CHECK(column(r.trajectory, "x").back() == Approx(1.75).margin(1e-8));
  for (int k = 1; k <= 3; ++k)
    CHECK(variable("e2e_logic_tables", r.trajectory, p, "w[" + std::to_string(k) + "]").back() == 3.0 + k);
}
