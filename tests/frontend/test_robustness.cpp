// A crash is never an answer: inputs that used to crash the front end get a
// result or a diagnostic (issue 10.1).
#include "compile.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>

using namespace mo::test;

namespace {

/// `der(x) = x - x - ... - x` with `terms` terms on one line.
std::string long_difference(int terms) {
  std::string rhs = "x";
  for (int i = 1; i < terms; ++i) rhs += " - x";
  return "model Deep\n  Real x(start = 1);\nequation\n  der(x) = " + rhs + ";\nend Deep;\n";
}

/// ../shared beside the checkout, else $MO_SHARED_DIR; empty if neither exists.
std::string shared_dir() {
  namespace fs = std::filesystem;
  const fs::path beside = fs::path(MO_SOURCE_DIR) / ".." / "shared";
  if (fs::exists(beside / "xcos-corpus")) return beside.string();
  if (const char *env = std::getenv("MO_SHARED_DIR"); env && fs::exists(fs::path(env) / "xcos-corpus"))
    return env;
  return {};
}

} // namespace

TEST_CASE("an array equation checks every element against its own right-hand side", "[robust]") {
  // Element 2 used to read element 1 of the right-hand side after it was moved out: a null
  // dereference in every model with an array equation (Coselica's planar frames, r = {..}).
  Compiled c = compile_text(R"(
    model Frames
      Real r[2], v[2];
    equation
      r = {cos(time), sin(time)};
      v = der(r);
    end Frames;)");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string text = c.model->print();
  CHECK(text.find("`r[2]` = sin(time);") != std::string::npos);
  CHECK(text.find("`v[2]` = der(`r[2]`);") != std::string::npos);
}

TEST_CASE("an array equation with a mismatched element kind is a diagnostic", "[robust]") {
  Compiled c = compile_text(R"(
    model Mixed
      Real r[2];
    equation
      r = {1.0, time > 1};
    end Mixed;)");
  CHECK_FALSE(c.ok());
  CHECK(c.diagnostics.find("sets a number equal to a Boolean") != std::string::npos);
}

TEST_CASE("a 20 000-term expression is rejected with a diagnostic, not a stack overflow", "[robust]") {
  Compiled c = compile_text(long_difference(20000));
  CHECK_FALSE(c.ok());
  CHECK(c.diagnostics.find("error: expression nested more than 1000 levels deep") != std::string::npos);
  CHECK(c.diagnostics.find("test.mo:4:") != std::string::npos);
}

TEST_CASE("long lists and many short statements are not deep", "[robust]") {
  std::string list = "0";
  for (int i = 1; i < 5000; ++i) list += ", -" + std::to_string(i);
  std::string eqs;
  for (int i = 0; i < 2000; ++i) eqs += "  y[" + std::to_string(i + 1) + "] = a[1] - a[2] - a[3] + time;\n";
  Compiled c = compile_text("model Wide\n  parameter Real a[5000] = {" + list + "};\n  Real y[2000];\nequation\n" +
                            eqs + "end Wide;\n");
  INFO(c.diagnostics.substr(0, 2000));
  CHECK(c.ok());
}

TEST_CASE("a 900-term expression flattens", "[robust]") {
  Compiled c = compile_text(long_difference(900));
  INFO(c.diagnostics);
  CHECK(c.ok());
}

TEST_CASE("a function's while-loop that never advances on a varying condition stops with a diagnostic",
          "[robust][functions]") {
  // Found by fuzz_flatten: `j := j + 0` grew j by one node per iteration, so
  // reaching the loop limit took minutes. The local now stays a literal.
  Compiled c = compile_text(R"(
    function first
      input Real table[:];
      input Real t0;
      output Integer index;
    protected
      Integer j = 1;
    algorithm
      while j <= size(table, 1) and table[j] <= t0 loop
        j := j + 0;
      end while;
      index := j;
    end first;
    model Stuck
      Integer i;
    initial algorithm
      i := first({0.5, 1}, time);
    equation
      when time > 1 then i = pre(i) + 1; end when;
    end Stuck;)");
  CHECK_FALSE(c.ok());
  CHECK(c.diagnostics.find("the while-loop runs more than 100000 times") != std::string::npos);
}

TEST_CASE("a loop that accumulates an expression stops with a diagnostic at a bounded size", "[robust][functions]") {
  const std::string grow = R"(
    function total
      input Real t;
      output Real y = 0;
    algorithm
      for k in 1:100000 loop
        y := y + t;
      end for;
    end total;
    model InFunction
      Real x = total(time);
    end InFunction;
    model InAlgorithm
      Real y;
    algorithm
      y := 0;
      for k in 1:100000 loop
        y := y + time;
      end for;
    end InAlgorithm;
    model Branching
      Real y;
    algorithm
      y := 1;
      for k in 1:40 loop
        if time > k then y := y + 1; else y := 2 * y; end if;
      end for;
    end Branching;)";
  // A value that doubles on each run (Branching) stops at 5 x max_elements
  // nodes: 5 * 10^6 by default (11 s and 2.5 GB for this model), 5000 here.
  mo::frontend::FlattenOptions options;
  options.max_elements = 1000;
  // In a function called by a continuous equation the value becomes a chain
  // of intermediate variables (200 terms each): it grows linearly, and the
  // loop stops at the bound on loop runs (10 x max_elements).
  Compiled f = compile({{"grow.mo", grow}}, "InFunction", options);
  INFO(f.diagnostics);
  CHECK_FALSE(f.ok());
  CHECK(f.diagnostics.find("grow.mo:6:7: error: the loops of algorithms and functions run more than 10000 times in "
                           "all") != std::string::npos);
  std::string shorter = grow;
  shorter.replace(shorter.find("100000"), 6, "9000");
  Compiled linear = compile({{"grow.mo", shorter}}, "InFunction", options);
  INFO(linear.diagnostics);
  REQUIRE(linear.ok());
  CHECK(linear.model->print().size() < 9000 * 2 * std::string(" + time").size());
  for (const char *model : {"InAlgorithm", "Branching"}) {
    Compiled a = compile({{"grow.mo", grow}}, model, options);
    INFO(model << ": " << a.diagnostics);
    CHECK_FALSE(a.ok());
    CHECK(a.diagnostics.find("this algorithm section cannot be flattened: the value of 'y' grows beyond 1000 "
                             "levels or 5000 terms") != std::string::npos);
  }
  // A large value is not a growing one: the MSL's NoiseExamples.Distributions
  // inlines values of 3.5 million nodes, 77 levels deep. Here 40000 terms.
  Compiled large = compile_text(R"(
    function g
      input Real p;
      output Real y;
    algorithm
      y := p * (p + 10);
    end g;
    model Large
      parameter Integer n = 10000;
      parameter Real c[n] = 1:n;
      Real x = g(c * fill(time, n));
    end Large;)");
  INFO(large.diagnostics.substr(0, 1000));
  CHECK(large.ok());
  // Linear growth meets the depth first, whatever the node bound.
  Compiled deep = compile({{"grow.mo", grow}}, "InAlgorithm");
  CHECK(deep.diagnostics.find("the value of 'y' grows beyond 1000 levels") != std::string::npos);
  // A string that doubles on each run of a loop stops at a million characters.
  Compiled text = compile_text(R"(
    function doubled
      input Integer n;
      output String s = "ab";
    algorithm
      for i in 1:n loop
        s := s + s;
      end for;
    end doubled;
    model Text
      parameter String t = doubled(40);
      Real x(start = 1);
    equation
      der(x) = -x;
    end Text;)");
  CHECK_FALSE(text.ok());
  CHECK(text.diagnostics.find("error: the joined string is longer than 1000000 characters") != std::string::npos);
  // Numbers fold as they are assigned: a long counting loop stays one literal.
  Compiled count = compile_text(R"(
    model Count
      Real y;
      Integer k;
    algorithm
      k := 0;
      while k < 50000 loop
        k := k + 1;
      end while;
      y := k * time;
    end Count;)");
  INFO(count.diagnostics);
  REQUIRE(count.ok());
  CHECK(count.model->print().find("  y = 50000 * time;\n") != std::string::npos);
}

TEST_CASE("a call of parameters whose inlined value grows large is evaluated instead", "[robust][functions]") {
  // y := y*y + a doubles y's expression on each run: 2^20 nodes after 20. Of
  // a parameter, the call is evaluated once the value passes 20000 nodes
  // (the MSL's Matrices.exp of a parameter matrix took a minute before); of
  // a time-varying argument it stays symbolic up to the general bound.
  const std::string src = R"(
    function iterate
      input Real a;
      input Integer n;
      output Real y = 0;
    algorithm
      for k in 1:n loop
        y := y * y + a;
      end for;
    end iterate;
    model OfParameter
      parameter Real a = 0.1;
      Real x = iterate(a, 20) * time;
    end OfParameter;
    model OfTime
      Real x = iterate(time, 12);
    end OfTime;)";
  Compiled p = compile({{"iterate.mo", src}}, "OfParameter");
  INFO(p.diagnostics);
  REQUIRE(p.ok());
  CHECK(p.diagnostics.find("iterate.mo:13:16: warning: function 'iterate' cannot be inlined (the value assigned to "
                           "'y' grows beyond 1000 levels or 20000 terms")
        != std::string::npos);
  double y = 0;
  for (int k = 0; k < 20; ++k)
    y = y * y + 0.1;
  const std::string printed = p.model->print();
  INFO(printed);
  CHECK(printed.find(fmt::format("  x = {} * time;", y)) != std::string::npos);
  // 2^12 nodes of a varying argument: inlined, no warning.
  Compiled t = compile({{"iterate.mo", src}}, "OfTime");
  INFO(t.diagnostics);
  REQUIRE(t.ok());
  CHECK(t.diagnostics.find("warning") == std::string::npos);
}

TEST_CASE("intermediates: only where a continuous equation calls the function, one per distinct value",
          "[robust][functions]") {
  // Each run of the loop reads s eight times: grow(x, 5) inlined as a tree
  // is 8^5 copies of x (300 000 characters), grow(x, 3) 960 nodes.
  const std::string src = R"(
    function grow
      input Real x;
      input Integer n;
      output Real s;
    algorithm
      s := x;
      for i in 1:n loop
        if s > 1 then
          s := s*s - s/(s + 1);
        else
          s := s + 0.5*s*s;
        end if;
      end for;
    end grow;
    function scaled "grow's rounds on a parameter, times a varying x"
      input Real x;
      input Real p;
      output Real y;
    protected
      Real s = p;
    algorithm
      for i in 1:5 loop
        if s > 1 then
          s := s*s - s/(s + 1);
        else
          s := s + 0.5*s*s;
        end if;
      end for;
      y := s*x;
    end scaled;
    model OfParameters
      parameter Real p = 0.3;
      Real x(start = 0.1, fixed = true);
      Real y;
    equation
      der(x) = -x;
      y = scaled(x, p);
    end OfParameters;
    model Once
      Real x(start = 0.1, fixed = true);
      Real y;
    equation
      der(x) = -x;
      y = grow(x, 5);
    end Once;
    model Again "the same call twice and as a binding: the same variables"
      Real x(start = 0.1, fixed = true);
      Real y;
      Real z;
      Real b = 3*grow(x, 5);
    equation
      der(x) = -x;
      y = grow(x, 5);
      z = 2*grow(x, 5);
    end Again;
    model Elsewhere "a parameter, a when-clause, an if-equation on a varying condition, an initial equation"
      parameter Real p = 0.3;
      parameter Real q = grow(p, 3);
      Real x(start = 0.1, fixed = true);
      discrete Real w;
      Real v;
      Real u;
    initial equation
      u = grow(x, 3);
    equation
      der(x) = -x;
      der(u) = 1;
      when x < 0.05 then
        w = grow(x, 3);
      end when;
      if x > 0.05 then
        v = grow(x, 3);
      else
        v = 0;
      end if;
    end Elsewhere;)";
  auto intermediates = [](const Compiled &c) {
    return std::count_if(c.model->variables.begin(), c.model->variables.end(),
                         [](const auto &v) { return v.name.rfind("_fn", 0) == 0; });
  };
  Compiled once = compile({{"grow.mo", src}}, "Once");
  INFO(once.diagnostics);
  REQUIRE(once.ok());
  const auto n = intermediates(once);
  CHECK(n > 0);
  const std::string printed = once.model->print();
  INFO(printed);
  CHECK(printed.size() < 30000);
  Compiled again = compile({{"grow.mo", src}}, "Again");
  INFO(again.diagnostics);
  REQUIRE(again.ok());
  CHECK(intermediates(again) == n);
  // The rounds on a parameter inside a call with a varying argument: their
  // values are parameters bound to them (a call of parameters only is
  // evaluated instead).
  Compiled of_parameters = compile({{"grow.mo", src}}, "OfParameters");
  INFO(of_parameters.diagnostics);
  REQUIRE(of_parameters.ok());
  const auto &vars = of_parameters.model->variables;
  CHECK(std::count_if(vars.begin(), vars.end(), [](const auto &v) {
          return v.name.rfind("_fn", 0) == 0 && v.variability == mo::frontend::ast::Variability::Parameter &&
                 v.binding;
        }) >= 5);
  CHECK(of_parameters.model->print().size() < 30000);
  Compiled elsewhere = compile({{"grow.mo", src}}, "Elsewhere");
  INFO(elsewhere.diagnostics);
  REQUIRE(elsewhere.ok());
  CHECK(intermediates(elsewhere) == 0);
  // The flat text, intermediates and all, flattens to itself.
  Compiled back = compile({{"once.mo", printed}});
  INFO(back.diagnostics);
  REQUIRE(back.ok());
  CHECK(back.model->print() == printed);
}

TEST_CASE("an array or a model beyond the element limit is a diagnostic, before it is built", "[robust]") {
  // Each of these took minutes and tens of GB before it was refused.
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"  Real x[100000, 100000];\n", "test.mo:2:8: error: 'x' has more than 1000000 elements"},
      {"  parameter Real a[:] = fill(1, 1000000, 1000000);\n", "error: fill() has more than 1000000 elements"},
      {"  parameter Real a[:, :] = fill({1, 2}, 1000, 1000);\n", "error: fill() has more than 1000000 elements"},
      {"  parameter Real a = sum(ones(100000, 100000));\n", "error: ones() has more than 1000000 elements"},
      {"  parameter Real a[:, :] = diagonal(1:2000);\n", "error: diagonal() has more than 1000000 elements"},
      {"  parameter Real a[:, :] = outerProduct(1:2000, 1:1000);\n",
       "error: outerProduct() has more than 1000000 elements"},
      {"  parameter Real a[:, :] = {i * j for i in 1:3000, j in 1:3000};\n",
       "error: the array constructor has more than 1000000 elements"},
      // Each of B's elements flattened A * A again, failing each time.
      {"  parameter Real A[300, 300] = fill(1, 300, 300);\n  parameter Real B[300, 300] = A * A;\n",
       "test.mo:3:32: error: the product has more than 1000000 multiplications"},
  };
  for (const auto &[decl, message] : cases) {
    Compiled c = compile_text("model Big\n" + decl + "  Real y;\nequation\n  der(y) = -y;\nend Big;\n");
    INFO(decl << c.diagnostics);
    CHECK_FALSE(c.ok());
    CHECK(c.diagnostics.find(message) != std::string::npos);
  }
  // The limit counts the model's scalar variables too; a smaller one shows it.
  mo::frontend::FlattenOptions small;
  small.max_elements = 1000;
  const std::string two = "model Two\n  Real a[600], b[600];\nequation\n  der(a) = -a;\n  der(b) = -b;\nend Two;\n";
  Compiled over = compile({{"two.mo", two}}, "Two", small);
  CHECK_FALSE(over.ok());
  CHECK(over.diagnostics.find("two.mo:2:16: error: the model has more than 1000 scalar variables") !=
        std::string::npos);
  // And the times for-equations run (`for i in 1:9000000` took minutes and 7.5 GB).
  Compiled loops = compile({{"loops.mo", "model Loops\n  Real x;\nequation\n  for i in 1:2000 loop\n    x = i;\n"
                                         "  end for;\nend Loops;\n"}},
                           "Loops", small);
  CHECK_FALSE(loops.ok());
  CHECK(loops.diagnostics.find("loops.mo:4:3: error: the model's for-equations run more than 1000 times") !=
        std::string::npos);
  // And the runs of loops in algorithms and functions, 10 times that in all.
  const std::string spin = R"(
    function spin
      input Real u;
      output Real y = 0;
    algorithm
      for i in 1:200 loop
        for j in 1:200 loop
        end for;
      end for;
      y := u;
    end spin;
    model Spin
      Real x = spin(time);
    end Spin;)";
  Compiled spun = compile({{"spin.mo", spin}}, "Spin", small);
  CHECK_FALSE(spun.ok());
  CHECK(spun.diagnostics.find("spin.mo:7:9: error: the loops of algorithms and functions run more than 10000 times") !=
        std::string::npos);
  small.max_elements = 1200;
  Compiled fits = compile({{"two.mo", two}}, "Two", small);
  INFO(fits.diagnostics);
  CHECK(fits.ok());
}

TEST_CASE("a 40 000-element array binding and its reductions flatten, nesting log-deep", "[robust]") {
  // Each element of `a` flattened the whole of `1:n` again (minutes), and
  // `a * a` nested 40 000 levels deep, which overflowed the evaluator's stack.
  Compiled c = compile_text(R"(
    model Long
      parameter Integer n = 40000;
      parameter Real a[n] = 1:n;
      parameter Real dot = a * a;
      parameter Real total = sum(a);
      parameter Real largest = max(a);
      Real x(start = 1);
    equation
      der(x) = -x;
    end Long;)");
  INFO(c.diagnostics.substr(0, 2000));
  REQUIRE(c.ok());
  const auto value = [&](const std::string &name) {
    const auto i = c.model->find(name);
    REQUIRE(i >= 0);
    REQUIRE(c.model->variables[i].value);
    return *c.model->variables[i].value;
  };
  const double n = 40000;
  CHECK(value("a[40000]") == n);
  CHECK(value("dot") == n * (n + 1) * (2 * n + 1) / 6);
  CHECK(value("total") == n * (n + 1) / 2);
  CHECK(value("largest") == n);
}

TEST_CASE("Coselica planar mechanics from Xcos flatten without crashing", "[robust][xcos]") {
  const std::string shared = shared_dir();
  const std::string electrical = std::string(MO_SCILAB_MACROS) + "/Electrical/Electrical.mo";
  if (shared.empty() || !std::filesystem::exists(electrical)) {
    WARN("SKIPPED: no ../shared (or MO_SHARED_DIR) or no Scilab macros");
    return;
  }
  const std::pair<const char *, const char *> models[] = {{"SimplePendulum", "SimplePendulum_im"},
                                                         {"CartWithPendulum3", "CartWithPendulum3_im"},
                                                         {"Crankshaft", "Connecting_RodCPGE_im"}};
  for (const auto &[name, cls] : models) {
    INFO(name);
    const std::string file = shared + "/xcos-corpus/flat/" + name + "_hier.mo";
    std::vector<Source> sources = {{"Coselica.mo", read_file(shared + "/third_party/coselica/Coselica.mo")},
                                   {"Electrical.mo", read_file(electrical)},
                                   {name + std::string("_hier.mo"), read_file(file)}};
    Compiled c = compile(sources, cls);
    INFO(c.diagnostics.substr(0, 3000));
    CHECK(c.ok());
  }
}

namespace {

/// Dotted paths of the non-partial models and blocks in `classes`, recursively.
void instantiable(const std::vector<mo::frontend::ast::ClassPtr> &classes, const std::string &prefix,
                  std::vector<std::string> &out) {
  using mo::frontend::ast::Restriction;
  for (const auto &c : classes) {
    const std::string path = prefix.empty() ? c->name : prefix + "." + c->name;
    if (!c->partial && (c->restriction == Restriction::Model || c->restriction == Restriction::Block))
      out.push_back(path);
    instantiable(c->classes, path, out);
  }
}

} // namespace

TEST_CASE("every model and block of the Coselica library flattens", "[robust][xcos]") {
  // Xcos diagrams are built from these blocks: each one alone (unconnected, so
  // not balanced) must flatten. The one exception is Coselica's own type
  // error, which Scilab's modelicat refuses too ("Type of operands
  // inconsistent with comparison operation"): `parameter Boolean
  // TorqueDirection = 1` compared with `> 0` in QuadraticSpeedDependentTorque.
  using namespace mo::frontend;
  const std::string shared = shared_dir();
  const std::string macros = MO_SCILAB_MACROS;
  if (shared.empty() || !std::filesystem::exists(macros + "/Electrical/Electrical.mo")) {
    WARN("SKIPPED: no ../shared (or MO_SHARED_DIR) or no Scilab macros");
    return;
  }
  SourceManager sm;
  DiagnosticEngine parse_diags(sm);
  Library lib;
  std::vector<std::string> classes;
  for (const std::string &path : {shared + "/third_party/coselica/Coselica.mo", macros + "/Electrical/Electrical.mo",
                                 macros + "/Hydraulics/Hydraulics.mo"}) {
    auto sd = parse(sm.add(path, read_file(path)), sm, parse_diags);
    REQUIRE(sd);
    if (path.find("Coselica") != std::string::npos) instantiable(sd->classes, "", classes);
    lib.add(std::move(sd));
  }
  REQUIRE(classes.size() > 500);
  std::vector<std::string> failed;
  for (const std::string &cls : classes) {
    DiagnosticEngine diags(sm);
    FlattenOptions options;
    options.check_balance = false;
    if (flatten(lib, cls, diags, options)) continue;
    std::ostringstream os;
    diags.print(os);
    INFO(cls << ": " << os.str().substr(0, 600));
    CHECK(os.str().find("the value of Boolean 'TorqueDirection' must be a Boolean, not a number") !=
          std::string::npos);
    failed.push_back(cls);
  }
  CHECK(failed == std::vector<std::string>{"Coselica.Mechanics.Rotational.Sources.QuadraticSpeedDependentTorque",
                                           "CMRS_QuadraticSpeedDepen"});
}
