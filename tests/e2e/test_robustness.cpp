// Results and failures that tell the truth (issues 10.6, 10.7, 12.6): result.csv
// holds every variable, NaN never reaches it with exit status 0, a failure
// names the equation or block (file.mo:line:col) and keeps the rows before it,
// Newton uses the variables' min/max/nominal.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "e2e/cli.hpp"
#include "e2e/support.hpp"

namespace fs = std::filesystem;
using namespace mo::e2e;

namespace {

/// Writes `text` to DIR/NAME.mo and returns its path.
fs::path model_file(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path p = dir / (name + ".mo");
  std::ofstream(p) << text;
  return p;
}

std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string f; std::getline(ss, f, ',');) out.push_back(f);
  return out;
}

/// The header and the rows of a CSV file.
struct Csv {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
  [[nodiscard]] std::size_t column(const std::string& name) const {
    return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
  }
};

Csv read_csv(const fs::path& path) {
  std::ifstream in(path);
  Csv c;
  std::string line;
  std::getline(in, line);
  c.names = fields(line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    for (const auto& f : fields(line)) row.push_back(std::stod(f));
    c.rows.push_back(row);
  }
  return c;
}

bool all_finite(const Csv& c) {
  for (const auto& r : c.rows)
    for (double v : r)
      if (!std::isfinite(v)) return false;
  return true;
}

const char* kAllVariables = R"(model AllVariables
  Real x(start = 1);
  Real a "solved for";
  Real b "an alias of a";
  Real c "a constant";
  output Real y;
  Integer n(start = 0) "a discrete variable";
equation
  der(x) = -a + c;
  when x < 0.6 then
    n = pre(n) + 1;
  end when;
  a = 2*x + sin(a)/10;
  b = a;
  c = 0.5;
  y = x + 1;
end AllVariables;
)";

}  // namespace

TEST_CASE("result.csv holds every variable of the model by default - --variables filters", "[robust]") {
  const fs::path dir = scratch("robust_all_variables");
  const fs::path mo = model_file(dir, "AllVariables", kAllVariables);
  const Run r = morun(quoted(mo.string()) + " --stop-time 1 --intervals 10 -o " + quoted((dir / "all").string()), dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const Csv all = read_csv(dir / "all" / "result.csv");
  for (const char* name : {"time", "x", "a", "b", "c", "y", "n"}) {
    INFO(name);
    CHECK(all.column(name) < all.names.size());
  }
  const auto& last = all.rows.back();
  CHECK(last[all.column("b")] == last[all.column("a")]);  // the alias under its own name
  CHECK(last[all.column("c")] == 0.5);
  CHECK(last[all.column("y")] == Approx(last[all.column("x")] + 1));
  CHECK(all.rows.front()[all.column("n")] == 0.0);  // as the last event left it: x < 0.6 once
  CHECK(last[all.column("n")] == 1.0);

  const Run f = morun(quoted(mo.string()) + " --stop-time 1 --intervals 10 --aliases --variables 'x|b' -o " +
                          quoted((dir / "some").string()),
                      dir);
  INFO(f.err);
  REQUIRE(f.status == 0);
  CHECK(read_csv(dir / "some" / "result.csv").names == std::vector<std::string>{"time", "x", "b"});

  const Run bad = morun(quoted(mo.string()) + " --stop-time 1 --variables '(' -o " + quoted((dir / "bad").string()), dir);
  CHECK(bad.status == 2);
  CHECK(bad.err.find("--variables") != std::string::npos);
}

TEST_CASE("sqrt of a negative number names the equation and keeps the rows before it", "[robust]") {
  const fs::path dir = scratch("robust_sqrt");
  const fs::path mo = model_file(dir, "SqrtOfNegative", R"(model SqrtOfNegative
  Real x(start = 1);
  output Real y;
equation
  der(x) = -1;
  y = sqrt(x);
end SqrtOfNegative;
)");
  const Run r = morun(quoted(mo.string()) + " --stop-time 2 --intervals 20 -o " + quoted((dir / "out").string()), dir);
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("SqrtOfNegative.mo:6:3: y = sqrt(x);") != std::string::npos);
  CHECK(r.err.find("with x = -") != std::string::npos);
  const Csv out = read_csv(dir / "out" / "result.csv");
  CHECK(all_finite(out));
  REQUIRE(!out.rows.empty());
  CHECK(out.rows.back()[0] == Approx(1.0));  // t = 0 .. 1: the rows before x < 0
  CHECK(slurp(dir / "out" / "summary.json").find("\"success\"") == std::string::npos);
}

namespace {

/// The bubble point of a binary mixture (Antoine's law): a nonlinear block in
/// T and the two vapour pressures, feeding a linear block whose coefficients
/// depend on T. From the start T = 288 K, Newton without bounds leaves the
/// physical range; with min/max/nominal it converges to T = 387.055 K, the
/// only root (P = pA z + pB (1 - z) there; the residual is 8e4 Pa at 371 K).
std::string bubble_point(const std::string& name, const std::string& temperature) {
  return "model " + name + R"(
  parameter Real a_A = 23.48, a_B = 22.437, b_A = 3626.6, b_B = 3166.4;
  parameter Real c_A = -34.29, c_B = -80.15, P = 187500;
  Real z(start = 0.0113, fixed = true);
  )" + temperature + R"(;
  Real pA, pB, V1, V2;
  output Real y = V1;
equation
  pA = exp(a_A - b_A/(T + c_A));
  pB = exp(a_B - b_B/(T + c_B));
  0 = (P - pA*z - pB*(1 - z))/P;
  T*V1 + V2 = 1;
  V1 - T*V2 = z;
  der(z) = -1e-3*V1;
end )" + name + ";\n";
}

}  // namespace

TEST_CASE("a non-finite derivative met inside the integrator names its equation", "[robust]") {
  // log(x - 0.5) is -inf at t = 0.5 and NaN after: CVODES rejects the steps
  // that reach it and stops with too much work, before any output row has
  // a NaN; the message must still say which equation.
  const fs::path dir = scratch("robust_log_inside");
  const fs::path mo = model_file(dir, "LogInside", R"(model LogInside
  Real x(start = 1);
  Real v(start = 0);
equation
  der(x) = -1;
  der(v) = log(x - 0.5);
end LogInside;
)");
  const Run r = morun(quoted(mo.string()) + " --stop-time 2 --intervals 20 -o " + quoted((dir / "out").string()), dir);
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("not finite at t = ") != std::string::npos);
  CHECK(r.err.find("LogInside.mo:6:3: der(v) = log(x - 0.5);") != std::string::npos);
  CHECK(r.err.find("with x = ") != std::string::npos);
  const Csv out = read_csv(dir / "out" / "result.csv");
  CHECK(all_finite(out));
  CHECK(slurp(dir / "out" / "summary.json").find("not finite at t = ") != std::string::npos);
}

TEST_CASE("Newton uses min, max and nominal: the bubble point converges", "[robust]") {
  const fs::path dir = scratch("robust_bubble_bounds");
  const fs::path mo = model_file(dir, "BubbleBounded", bubble_point("BubbleBounded",
      "Real T(start = 288.15, min = 0, max = 511.9, nominal = 300)"));
  const Run r = morun(quoted(mo.string()) + " --stop-time 1 --intervals 10 -o " + quoted((dir / "out").string()), dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const Csv out = read_csv(dir / "out" / "result.csv");
  CHECK(all_finite(out));
  CHECK(out.rows.front()[out.column("T")] == Approx(387.0552).margin(1e-3));
}

TEST_CASE("a diverging nonlinear block is reported as itself, with its equations, exit 1", "[robust]") {
  // exp(T/100) + z has no root for z > 0: Newton fails on T, and the linear
  // block after it (its coefficients depend on T) must not be blamed.
  const fs::path dir = scratch("robust_no_root");
  const fs::path mo = model_file(dir, "NoRoot", R"(model NoRoot
  Real z(start = 1, fixed = true);
  Real T(start = 300), V1, V2;
equation
  0 = exp(T/100) + z;
  T*V1 + V2 = 1;
  V1 - T*V2 = z;
  der(z) = -1e-3*V1;
end NoRoot;
)");
  const Run r = morun(quoted(mo.string()) + " --stop-time 1 --intervals 10 -o " + quoted((dir / "out").string()), dir);
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("nonlinear block 1 for T at t = 0") != std::string::npos);
  CHECK(r.err.find("NoRoot.mo:5:3: 0 = exp(T/100) + z;") != std::string::npos);
  CHECK(r.err.find("linear block 2") == std::string::npos);  // not the linear block downstream
  if (fs::exists(dir / "out" / "result.csv")) CHECK(all_finite(read_csv(dir / "out" / "result.csv")));
}

TEST_CASE("an inconsistent or structurally singular model is an error before simulating", "[robust]") {
  const fs::path dir = scratch("robust_inconsistent");
  const fs::path mo = model_file(dir, "Inconsistent", R"(model Inconsistent
  Real x, y;
equation
  x + y = 1;
  x + y = 2;
end Inconsistent;
)");
  const Run r = morun(quoted(mo.string()) + " --stop-time 1 -o " + quoted((dir / "out").string()), dir);
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("Inconsistent.mo:") != std::string::npos);
  CHECK(r.err.find("error:") != std::string::npos);
  CHECK(r.err.find("singular") != std::string::npos);
  CHECK(r.err.find("these 1 equations") == std::string::npos);
  CHECK(r.err.find("no states") == std::string::npos);
}

TEST_CASE("a 900-term expression goes through lowering, printing, C++ and simulation", "[robust]") {
  const fs::path dir = scratch("robust_deep");
  std::string rhs = "x";
  for (int i = 1; i < 900; ++i) rhs += " - x";  // = -898 x
  const fs::path mo = model_file(dir, "Deep", "model Deep\n  Real x(start = 1);\nequation\n  der(x) = " + rhs +
                                                  ";\nend Deep;\n");
  const Run r = morun(quoted(mo.string()) + " --stop-time 0.005 --intervals 5 --rtol 1e-8 --atol 1e-12 -o " +
                          quoted((dir / "out").string()),
                      dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const Csv out = read_csv(dir / "out" / "result.csv");
  CHECK(out.rows.back()[out.column("x")] == Approx(std::exp(-898 * 0.005)).epsilon(1e-4));
}
