// The parts of Modelica the Modelica Standard Library leans on: user
// functions inlined, external "builtin" functions, String(), predefined
// enumerations, imports of constants, local and repeated base classes,
// connectors extending Real. Each model here is a small case of its kind.
#include "compile.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>

using namespace mo::test;

namespace {

std::string flat(const std::string &text, const std::string &cls = "") {
  Compiled c = compile_text(text, cls);
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  return c.model->print();
}

double value(const std::string &text, const std::string &var) {
  Compiled c = compile_text(text);
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const auto i = c.model->find(var);
  REQUIRE(i >= 0);
  REQUIRE(c.model->variables[i].value);
  return *c.model->variables[i].value;
}

bool contains(const std::string &s, const std::string &part) { return s.find(part) != std::string::npos; }

/// ../shared beside the checkout, or $MO_SHARED_DIR; empty when neither exists.
std::string shared_dir() {
  namespace fs = std::filesystem;
  const fs::path beside = fs::path(MO_SOURCE_DIR) / ".." / "shared";
  if (fs::is_directory(beside / "third_party"))
    return beside.string();
  if (const char *env = std::getenv("MO_SHARED_DIR"); env && fs::is_directory(env))
    return env;
  return "";
}

} // namespace

TEST_CASE("import clauses inside a class bring constants and aliases", "[msl]") {
  const char *src = R"(
    package Consts
      constant Real two = 2;
      constant Real three = 3;
    end Consts;
    model Uses
      import Consts.two;
      import C = Consts;
      import Consts.*;
      parameter Real a = two;
      parameter Real b = C.three;
      parameter Real c = three;
    end Uses;)";
  CHECK(value(src, "a") == 2);
  CHECK(value(src, "b") == 3);
  CHECK(value(src, "c") == 3);
}

TEST_CASE("a class may extend a class declared inside it", "[msl]") {
  std::string s = flat(R"(
    model Outer
      partial model Inner
        Real v(start = 2, fixed = true);
      end Inner;
      extends Inner;
    equation
      der(v) = -2 * v;
    end Outer;)");
  CHECK(contains(s, "Real v(start = 2, fixed = true);"));
}

TEST_CASE("a base inherited along two paths is merged", "[msl]") {
  std::string s = flat(R"(
    package P
      partial model Len
        parameter Real len = 1;
      equation
        assert(len > 0, "len must be positive");
      end Len;
      model Mid
        extends Len;
      end Mid;
      model Both
        extends Mid;
        extends Len;
        Real y(start = 0, fixed = true);
      equation
        der(y) = len;
      end Both;
    end P;)", "P.Both");
  CHECK(contains(s, "parameter Real len = 1;"));
  // The base's equations appear once.
  CHECK(s.find("assert(") == s.rfind("assert("));
  // A second path with its own modifiers is not an identical duplicate.
  Compiled c = compile_text(R"(
    model Len
      parameter Real len = 1;
    end Len;
    model Mid
      extends Len;
    end Mid;
    model Both
      extends Mid;
      extends Len(len = 2);
    end Both;)");
  CHECK_FALSE(c.ok());
  CHECK(contains(c.diagnostics, "'Len' is inherited again with other modifiers"));
}

TEST_CASE("a connector extending Real is a Real connector", "[msl]") {
  std::string s = flat(R"(
    package Sig
      connector Signal
        extends Real;
      end Signal;
      connector In = input Signal;
      connector Out = output Signal;
      block Twice
        In u;
        Out y;
      equation
        y = 2 * u;
      end Twice;
      model Loop
        Twice t;
        Real z(start = 1, fixed = true);
      equation
        t.u = z;
        der(z) = -t.y;
      end Loop;
    end Sig;)", "Sig.Loop");
  CHECK(contains(s, "input Real `t.u`;"));
  CHECK(contains(s, "output Real `t.y`;"));
}

TEST_CASE("StateSelect and AssertionLevel are predefined enumerations", "[msl]") {
  const char *src = R"(
    model Sel
      parameter StateSelect s = StateSelect.avoid;
      parameter AssertionLevel level = AssertionLevel.warning;
      Real x(start = 1, fixed = true, stateSelect = s);
    equation
      der(x) = -x;
    end Sel;)";
  CHECK(value(src, "s") == 2);
  CHECK(value(src, "level") == 2);
}

TEST_CASE("String() in an assert message", "[msl]") {
  std::string s = flat(R"(
    model Msg
      Real x(start = 1, fixed = true);
    equation
      der(x) = -x;
      assert(x > 0, "x is " + String(x) + ", not positive");
    end Msg;)");
  CHECK(contains(s, "String(x)"));
}

TEST_CASE("external builtin functions are the built-ins they name", "[msl][functions]") {
  const char *src = R"(
    package Lib
      package Math
        function asin
          input Real u;
          output Real y;
        external "builtin" y = asin(u);
        end asin;
        function cosine
          input Real u;
          output Real y;
        external "builtin";
        end cosine;
      end Math;
      package Constants
        final constant Real pi = 2 * Math.asin(1.0);
      end Constants;
    end Lib;
    model Circle
      parameter Real r = Lib.Constants.pi;
      Real x;
    equation
      x = Lib.Math.asin(sin(time));
    end Circle;)";
  CHECK(value(src, "r") == Approx(3.14159265358979));
  CHECK(contains(flat(src), "x = asin(sin(time));"));
}

TEST_CASE("functions with straight-line algorithms are inlined", "[msl][functions]") {
  const char *src = R"(
    function affine
      input Real x;
      input Real a = 2;
      input Real b = a + 1;
      output Real y;
    protected
      Real t;
    algorithm
      t := a * x;
      y := t + b;
    end affine;
    model Use
      parameter Real p1 = affine(1);
      parameter Real p2 = affine(1, 3);
      parameter Real p3 = affine(1, b = 10);
      Real z;
    equation
      z = affine(time, a = 5);
    end Use;)";
  CHECK(value(src, "p1") == 5);
  CHECK(value(src, "p2") == 7);
  CHECK(value(src, "p3") == 12);
  CHECK(contains(flat(src), "z = 5 * time + (5 + 1);"));
}

TEST_CASE("if statements become if-expressions, constant ones pick a branch", "[msl][functions]") {
  const char *src = R"(
    function clip
      input Real u;
      input Real limit;
      output Real y;
    algorithm
      if limit <= 0 then
        y := 0;
      elseif u > limit then
        y := limit;
      elseif u < -limit then
        y := -limit;
      else
        y := u;
      end if;
    end clip;
    model Use
      parameter Real c = clip(5, 2);
      Real z;
    equation
      z = clip(time, 1);
    end Use;)";
  CHECK(value(src, "c") == 2);
  // Relations in a function's body generate no events (no GenerateEvents).
  CHECK(contains(flat(src), "z = if noEvent(time > 1) then 1 else if noEvent(time < -1) then -1 else time;"));
}

TEST_CASE("a function's relations are noEvent unless it generates events or returns a discrete value",
          "[msl][functions]") {
  const char *src = R"(
    function ramp
      input Real u;
      output Real y;
    algorithm
      y := if u > 0 then u else 0;
    end ramp;
    function twice "calls ramp: no events either"
      input Real u;
      output Real y;
    algorithm
      y := 2 * ramp(u - 1);
    end twice;
    function rampEvents
      input Real u;
      output Real y;
    algorithm
      y := if u > 0 then u else 0;
      annotation(GenerateEvents = true);
    end rampEvents;
    function steps "an Integer output: events"
      input Real u;
      output Integer n;
    algorithm
      n := if u > 1 then 2 else 1;
    end steps;
    model Use
      Real a = ramp(if time > 3 then time else 0);
      Real b = twice(time);
      Real c = rampEvents(time);
      Integer n = steps(time);
    end Use;)";
  const std::string s = flat(src);
  INFO(s);
  CHECK(contains(s, "a = if noEvent((if time > 3 then time else 0) > 0) then if time > 3 then time else 0 else 0;"));
  CHECK(contains(s, "b = 2 * (if noEvent(time - 1 > 0) then time - 1 else 0);"));
  CHECK(contains(s, "c = if time > 0 then time else 0;"));
  CHECK(contains(s, "n = if time > 1 then 2 else 1;"));
}

TEST_CASE("semiLinear on a two-component connection: the port value by MLS 3.7.2.5 rule 1, both forms",
          "[msl][connections]") {
  // The shared value as the positive-flow argument (FluidHeatFlow's form)
  // and as the negative-flow one; x = the first component's mass flow.
  const char *src = R"(
    model Rule
      connector Port flow Real m; flow Real H; Real h; end Port;
      model Own parameter Real q; input Real m; Port port;
      equation port.m = m; port.H = semiLinear(port.m, port.h, q); end Own;
      model Back parameter Real q; Port port;
      equation port.H = semiLinear(port.m, q, port.h); end Back;
      model OwnSink parameter Real q; Port port;
      equation port.H = semiLinear(port.m, port.h, q); end OwnSink;
      model BackSource parameter Real q; input Real m; Port port;
      equation port.m = m; port.H = semiLinear(port.m, q, port.h); end BackSource;
      Own a(q = 1, m = time - 1);
      OwnSink b(q = 2);
      BackSource c(q = 3, m = time - 1);
      Back d(q = 4);
    equation
      connect(a.port, b.port);
      connect(c.port, d.port);
    end Rule;)";
  const std::string s = flat(src);
  INFO(s);
  CHECK(contains(s, "`a.port.h` = if `a.port.m` >= 0. then `b.q` else `a.q`;"));
  CHECK(contains(s, "`c.port.h` = if `c.port.m` >= 0. then `c.q` else `d.q`;"));
  CHECK(contains(s, "`b.port.H` = if `b.port.m` >= 0. then"));  // the second component keeps its own
  CHECK(contains(s, "`d.port.H` = if `d.port.m` >= 0. then"));
}

TEST_CASE("semiLinear of arrays is taken element by element, of empty ones is empty", "[msl][connections]") {
  // Modelica.Media's test models: `port.mXi_flow = semiLinear(port.m_flow,
  // port.Xi, medium.Xi)`, Xi of size 0 for a single substance.
  const std::string s = flat(R"(
    model Vec
      Real m = time - 1;
      Real a[2] = {1, 2};
      Real b[2] = {3, 4};
      Real y[2] = semiLinear(m, a, b);
      Real e[0] = semiLinear(m, fill(0.0, 0), fill(0.0, 0));
    end Vec;)");
  INFO(s);
  CHECK(contains(s, "`y[1]` = if m >= 0. then `a[1]` * m else `b[1]` * m;"));
  CHECK(contains(s, "`y[2]` = if m >= 0. then `a[2]` * m else `b[2]` * m;"));
  CHECK_FALSE(contains(s, "e["));
}

TEST_CASE("for loops are unrolled, while loops run on constants, several outputs", "[msl][functions]") {
  const char *src = R"(
    function poly "Horner's scheme"
      input Real c[:];
      input Real x;
      output Real y;
    algorithm
      y := 0;
      for i in 1:size(c, 1) loop
        y := y * x + c[i];
      end for;
    end poly;
    function halvings
      input Real x;
      output Integer n;
      output Real rest;
    algorithm
      n := 0;
      rest := x;
      while rest > 1 loop
        rest := rest / 2;
        n := n + 1;
      end while;
    end halvings;
    function squares
      input Integer n;
      output Real s[n];
    algorithm
      for i in 1:n loop
        s[i] := i * i;
      end for;
    end squares;
    model Use
      parameter Real p = poly({1, 2, 3}, 2);
      parameter Integer h = halvings(20);
      parameter Real sq[3] = squares(3);
      Real z;
    equation
      z = poly({2, 0}, time);
    end Use;)";
  CHECK(value(src, "p") == 11);
  CHECK(value(src, "h") == 5);
  CHECK(value(src, "sq[3]") == 9);
  CHECK(contains(flat(src), "z = (0 * time + 2) * time + 0;"));
}

TEST_CASE("what cannot be inlined gets a diagnostic", "[msl][functions]") {
  auto diag = [](const std::string &src) {
    Compiled c = compile_text(src);
    CHECK_FALSE(c.ok());
    return c.diagnostics;
  };
  CHECK(contains(diag(R"(
    function f
      input Real u;
      output Real y;
    algorithm
      y := u;
      while y < 10 loop
        y := y + 1;
      end while;
    end f;
    model M
      Real z = f(time);
    end M;)"),
                 "more than 128 conditions that vary decide one way through the algorithm"));
  CHECK(contains(diag(R"(
    function g
      input Real u;
      output Real y;
    external "C" y = g_impl(u);
    end g;
    model M
      Real z = g(time);
    end M;)"),
                 "only external \"builtin\" functions are supported"));
  CHECK(contains(diag(R"(
    function h
      input Real u;
      output Real y;
    algorithm
      y := u;
    end h;
    model M
      Real z = h();
    end M;)"),
                 "input 'u' of function 'h' is missing and has no default"));
}

TEST_CASE("parameters that sized an array choose a function's branch", "[msl][functions]") {
  // As the MSL's filter coefficients: the branches of the other orders index
  // past this order's sizes.
  const char *src = R"(
    function coefficients
      input Integer order;
      output Real c[order];
    algorithm
      if order == 1 then
        c[1] := 0.5;
      elseif order == 2 then
        c[1] := 2;
        c[2] := 3;
      end if;
    end coefficients;
    model Use
      parameter Integer n = 1;
      parameter Real c[n] = coefficients(n);
      Real x(start = 1, fixed = true);
    equation
      der(x) = -c[1] * x;
    end Use;)";
  CHECK(value(src, "c[1]") == 0.5);
}

TEST_CASE("a function that cannot be inlined but has parameter arguments is evaluated, with a warning",
          "[msl][functions]") {
  // Bisection to a tolerance behind an error() guard, as the MSL's
  // normalizationFactor: symbolically the guard's branch cannot be dropped.
  const char *src = R"(
    function root
      input Real a;
      output Real x;
    protected
      Real lo = 0;
      Real hi = max(1, a);
      Real mid;
    algorithm
      if a < 0 then
        error("no real root");
      end if;
      while hi - lo > 1e-12 loop
        mid := (lo + hi) / 2;
        if mid * mid > a then
          hi := mid;
        else
          lo := mid;
        end if;
      end while;
      x := sqrt(lo) * sqrt(lo);
    end root;
    model Use
      parameter Real a = 2;
      parameter Real r = root(a);
      Real z;
    equation
      z = r * time;
    end Use;)";
  Compiled c = compile_text(src);
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  CHECK(contains(c.diagnostics, "warning: function 'root' cannot be inlined"));
  const auto i = c.model->find("r");
  REQUIRE(i >= 0);
  REQUIRE(c.model->variables[i].value);
  CHECK(*c.model->variables[i].value == Approx(std::sqrt(2.0)).epsilon(1e-11));
  // With a time-varying argument it stays an error.
  Compiled varying = compile_text(R"(
    function twice
      input Real u;
      output Real y;
    algorithm
      if u < 0 then
        error("negative");
      end if;
      y := 2 * u;
    end twice;
    model M
      Real z = twice(time);
    end M;)");
  CHECK_FALSE(varying.ok());
  CHECK(contains(varying.diagnostics, "cannot inline function 'twice'"));
}

TEST_CASE("pre(), noEvent() and edge() have their argument's kind of value", "[msl][types]") {
  // As the MSL's OnOffController: `initial equation pre(y) = pre_y_start;`.
  const char *src = R"(
    model OnOff
      parameter Boolean y0 = false;
      Boolean y;
      Boolean rising;
      Real u = sin(time);
    initial equation
      pre(y) = y0;
    equation
      y = pre(y) and u < 0.5 or u < -0.5;
      rising = edge(y);
    end OnOff;)";
  Compiled c = compile_text(src);
  INFO(c.diagnostics);
  CHECK(c.ok());
  CHECK_FALSE(contains(c.diagnostics, "equal to"));
  Compiled wrong = compile_text(R"(
    model M
      Boolean b;
      Real x;
    equation
      b = time > 1;
      x = pre(b);
    end M;)");
  CHECK(contains(wrong.diagnostics, "this equation sets a number equal to a Boolean"));
}

TEST_CASE("Modelica.Constants.pi with the MSL on the lookup path", "[msl][lookup]") {
  const std::string shared = shared_dir();
  if (shared.empty()) {
    WARN("SKIPPED: no ../shared/third_party (set MO_SHARED_DIR)");
    return;
  }
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("mo_msl_pi_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write_file((dir / "UsesPi.mo").string(),
             "model UsesPi\n  import Modelica.Constants.pi;\n  parameter Real tau = 2 * pi;\n"
             "  Real phi(start = 0, fixed = true);\nequation\n  der(phi) = tau;\nend UsesPi;\n");
  const std::string cmd = "MODELICAPATH=" + shared + "/third_party/msl-3.2.2 " + MO_MOCOMPILE + " " +
                          (dir / "UsesPi.mo").string() + " > " + (dir / "out.txt").string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  const std::string out = read_file((dir / "out.txt").string());
  fs::remove_all(dir);
  INFO(out);
  CHECK(WEXITSTATUS(status) == 0);
  CHECK(contains(out, "parameter Real tau = 2 * 3.14159"));
}

// Matrices.integralExpT calls `exp(F, T)`: its own package's matrix
// exponential (MLS 5.3.1), not the built-in. Of parameters, it is evaluated
// (the series branches on their values); exp of [1 2; 3 4] * 1.1 and the
// integrals, checked against a scaled-and-squared Taylor series.
TEST_CASE("the MSL's matrix exponential is found before the built-in exp", "[msl][lookup]") {
  const std::string shared = shared_dir();
  if (shared.empty()) {
    WARN("SKIPPED: no ../shared/third_party (set MO_SHARED_DIR)");
    return;
  }
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("mo_msl_expm_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write_file((dir / "Expm.mo").string(), R"(model Expm
  parameter Real A[2, 2] = {{1, 2}, {3, 4}};
  parameter Real B[2, 1] = {{1}, {1}};
  Real phi[2, 2];
  Real g[2, 1];
  Real g1[2, 1];
equation
  (phi, g, g1) = Modelica.Math.Matrices.integralExpT(A, B, 1.1);
end Expm;
)");
  const std::string cmd = "MODELICAPATH=" + shared + "/third_party/msl-3.2.2 " + MO_MOCOMPILE + " " +
                          (dir / "Expm.mo").string() + " > " + (dir / "out.txt").string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  const std::string out = read_file((dir / "out.txt").string());
  fs::remove_all(dir);
  INFO(out);
  REQUIRE(WEXITSTATUS(status) == 0);
  CHECK(contains(out, "warning: function 'Modelica.Math.Matrices.exp' cannot be inlined"));
  const std::pair<const char *, double> expected[] = {
      {"`phi[1,1]` = ", 88.539990301}, {"`phi[1,2]` = ", 128.072885534}, {"`phi[2,1]` = ", 192.109328301},
      {"`phi[2,2]` = ", 280.649318588}, {"`g[1,1]` = ", 40.532895237},    {"`g[2,1]` = ", 87.539990296},
      {"`g1[1,1]` = ", 7.574199825},    {"`g1[2,1]` = ", 15.929347706}};
  for (const auto &[lhs, v] : expected) {
    const auto at = out.find(lhs);
    REQUIRE(at != std::string::npos);
    CHECK(std::stod(out.substr(at + std::string(lhs).size())) == Approx(v).epsilon(1e-8));
  }
}

TEST_CASE("connections to a switched-off conditional component are removed", "[msl]") {
  std::string s = flat(R"(
    connector Pin
      Real v;
      flow Real i;
    end Pin;
    model Ground
      Pin p;
    equation
      p.v = 0;
    end Ground;
    model Circuit
      parameter Boolean grounded = false;
      Pin a;
      Ground g if grounded;
      Real x(start = 1, fixed = true);
    equation
      connect(a, g.p);
      a.v = x;
      der(x) = -x;
    end Circuit;)");
  CHECK_FALSE(contains(s, "g.p"));
}

TEST_CASE("connections through arrays of components to their switched-off connectors are removed", "[msl]") {
  // MultiPhase.Basic.Resistor: `Resistor resistor[m](each useHeatPort = useHeatPort)`
  // and `connect(resistor.heatPort, heatPort)` with both heat ports conditional.
  const std::string model = R"(
    connector HeatPort
      Real T;
      flow Real Q_flow;
    end HeatPort;
    model Element
      parameter Boolean useHeatPort = false;
      HeatPort heatPort if useHeatPort;
      Real x(start = 1, fixed = true);
    equation
      der(x) = -x;
    end Element;
    model Phases
      parameter Integer m = 3;
      parameter Boolean useHeatPort = false;
      Element e[m](each useHeatPort = useHeatPort);
      HeatPort heatPort[m] if useHeatPort;
    equation
      connect(e.heatPort, heatPort);
    end Phases;
    model Off
      Phases p;
    end Off;
    model On
      Phases p(useHeatPort = true);
    end On;)";
  Compiled off = compile_text(model, "Off");
  INFO(off.diagnostics);
  REQUIRE(off.ok());
  CHECK_FALSE(contains(off.model->print(), "heatPort"));
  // Switched on, the connections are made: p.e[k].heatPort.T = p.heatPort[k].T.
  Compiled on = compile({{"on.mo", model}}, "On", false);
  INFO(on.diagnostics);
  REQUIRE(on.ok());
  CHECK(contains(on.model->print(), "p.heatPort[3].T"));
  CHECK(contains(on.model->print(), "p.e[3].heatPort.T"));
}

TEST_CASE("connected parameters give no equations - different values are an error", "[msl]") {
  // The MSL's multi-phase plugs carry their phase count: `connector Plug
  // parameter Integer m = 3; Pin pin[m]; end Plug;` (9.2: no equation for it).
  const std::string lib = R"(
    connector Pin
      Real v;
      flow Real i;
    end Pin;
    connector Plug
      parameter Integer m = 3;
      Pin pin[m];
    end Plug;
    model Load
      parameter Integer m = 3;
      Plug plug(final m = m);
    equation
      plug.pin.v = plug.pin.i;
    end Load;
    model Source
      parameter Integer m = 3;
      Plug plug(final m = m);
    equation
      plug.pin.v = fill(sin(time), m);
    end Source;
  )";
  Compiled c = compile_text(lib + R"(
    model Circuit
      Source s;
      Load l;
    equation
      connect(s.plug, l.plug);
    end Circuit;)",
                            "Circuit");
  INFO(c.diagnostics);
  REQUIRE(c.ok()); // balanced: 6 pin equations, 3 + 3 connection equations for 12 unknowns
  CHECK_FALSE(contains(c.model->print(), "`s.plug.m` = `l.plug.m`"));
  Compiled mismatch = compile_text(R"(
    connector Port
      parameter Real k = 1;
      Real v;
      flow Real i;
    end Port;
    model End
      Port port;
    equation
      port.v = port.i;
    end End;
    model Pair
      End a(port(k = 1)), b(port(k = 2));
    equation
      connect(a.port, b.port);
    end Pair;)",
                                   "Pair");
  INFO(mismatch.diagnostics);
  CHECK(contains(mismatch.diagnostics, "connected parameters 'a.port.k' = 1 and 'b.port.k' = 2 differ"));
  CHECK_FALSE(mismatch.ok());
}

TEST_CASE("a Boolean constant passed on in a modifier stays a Boolean", "[msl]") {
  // Machines' PartialBasicDCMachine: `InductorDC la(final quasiStationary = quasiStationary)`
  // with `constant Boolean quasiStationary = false` declared after it.
  std::string s = flat(R"(
    model Ind
      parameter Boolean quasiStationary(start = false);
      Real i(start = 0, fixed = true);
    equation
      der(i) = if quasiStationary then 0 else 1;
    end Ind;
    partial model Machine
      Ind la(final quasiStationary = quasiStationary);
      constant Boolean quasiStationary = true;
    end Machine;
    model Dc
      extends Machine;
    end Dc;
    model Top
      Dc m;
    end Top;)", "Top");
  CHECK(contains(s, "parameter Boolean `m.la.quasiStationary`(start = false) = true;"));
}

TEST_CASE("an element declared again with other attributes than its base's is merged, with a warning",
          "[msl]") {
  // MultiPhase.Basic.MutualInductor declares `parameter Integer m = 3` over
  // TwoPlug's `parameter Integer m(min = 1) = 3`.
  Compiled c = compile_text(R"(
    partial model TwoPlug
      parameter Integer m(min = 1) = 3 "Number of phases";
      Real v[m];
    end TwoPlug;
    model Mutual
      extends TwoPlug;
      parameter Integer m = 3 "Number of phases";
    equation
      v = fill(time, m);
    end Mutual;)");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  CHECK(contains(c.diagnostics, "warning: 'm' is also declared by a base class, with other attributes"));
  CHECK(contains(c.model->print(), "parameter Integer m(min = 1) = 3"));
  // Another value is no duplicate: an error, as before.
  Compiled other = compile_text(R"(
    partial model TwoPlug
      parameter Integer m = 3;
    end TwoPlug;
    model Mutual
      extends TwoPlug;
      parameter Integer m = 4;
    end Mutual;)");
  CHECK_FALSE(other.ok());
  CHECK(contains(other.diagnostics, "error: duplicate declaration of 'm'"));
}

TEST_CASE("a component's condition uses the instance's modified parameter, declared after it or not",
          "[msl]") {
  // As the MSL's LimPID: `D ... if with_D` above `parameter Boolean with_D = ...`.
  const std::string s = flat(R"(
    package P
      type Kind = enumeration(PI, PID);
      block Controller
        parameter Kind kind = Kind.PID;
        Real d = 1 if with_D;
        Real zero = 0 if not with_D;
      protected
        parameter Boolean with_D = kind == Kind.PID;
      end Controller;
      model Top
        Controller c(kind = Kind.PI);
      end Top;
    end P;)",
                             "P.Top");
  CHECK(contains(s, "c.zero"));
  CHECK_FALSE(contains(s, "c.d`"));
}

TEST_CASE("a fixed = false parameter given explicitly by an initial equation gets it as binding",
          "[msl][initial]") {
  // As the MSL's filters: coefficients from tuple equations of functions of
  // the order, then from functions of those coefficients.
  const char *src = R"(
    function prototype
      input Integer order;
      output Real c[order];
    algorithm
      for i in 1:order loop
        c[i] := i / 2;
      end for;
    end prototype;
    function scaled
      input Real c[:];
      input Real f;
      output Real a[size(c, 1)];
      output Real total;
    algorithm
      total := 0;
      for i in 1:size(c, 1) loop
        a[i] := c[i] * f;
        total := total + a[i];
      end for;
    end scaled;
    model Coefficients
      parameter Integer n = 2;
      parameter Real f = 3;
      parameter Real c[n](each fixed = false);
      parameter Real a[n](each fixed = false);
      parameter Real total(fixed = false);
      parameter Real implicit(fixed = false, start = 1);
      Real x(start = 1, fixed = true);
    initial equation
      c = prototype(n);
      (a, total) = scaled(c, f);
      implicit * implicit = f;
    equation
      der(x) = -total * x;
    end Coefficients;)";
  Compiled c = compile_text(src);
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string s = c.model->print();
  CHECK(contains(s, "parameter Real `a[2]` ="));
  CHECK(contains(s, "parameter Real total ="));
  // Implicit in the parameter: stays an initial equation.
  CHECK(contains(s, "implicit * implicit = f"));
  CHECK(value(src, "total") == Approx(4.5));
  CHECK(value(src, "a[2]") == Approx(3));
}

TEST_CASE("tuple equations take the outputs of a function, size() of an unassigned output", "[msl][functions]") {
  const char *src = R"(
    function split
      input Integer n;
      input Real x;
      output Real parts[n];
      output Real total;
    algorithm
      for i in 1:size(parts, 1) loop
        parts[i] := x / n;
      end for;
      total := x;
    end split;
    model Use
      parameter Real p[2](each fixed = false);
      parameter Real q(fixed = false);
      Real a[3];
      Real b;
    initial equation
      (p, q) = split(2, 6);
    equation
      (a, ) = split(3, time);
      (, b) = split(1, 2 * time);
    end Use;)";
  const std::string s = flat(src);
  CHECK(contains(s, "`a[3]` = time / 3;"));
  CHECK(contains(s, "b = 2 * time;"));
  CHECK(contains(s, "`p[2]` = 3.;"));
  CHECK(contains(s, "q = 6;"));
  Compiled bad = compile_text(R"(
    model Bad
      Real a, b;
    equation
      (a, b) = sin(time);
    end Bad;)");
  CHECK(contains(bad.diagnostics, "the right side of a tuple equation must call a user function"));
}

TEST_CASE("while, return and break on varying conditions become if-expressions over the ways through",
          "[msl][functions]") {
  const char *src = R"(
    function interp
      input Real x[:];
      input Real y[size(x, 1)];
      input Real xi;
      input Integer iLast = 1;
      output Real yi;
      output Integer iNew = 1;
    protected
      Integer i;
      Integer nx = size(x, 1);
    algorithm
      i := min(max(iLast, 1), nx - 1);
      if xi >= x[i] then
        while i < nx and xi >= x[i] loop
          i := i + 1;
        end while;
        i := i - 1;
      else
        while i > 1 and xi < x[i] loop
          i := i - 1;
        end while;
      end if;
      yi := y[i] + (y[i + 1] - y[i]) * (xi - x[i]) / (x[i + 1] - x[i]);
      iNew := i;
    end interp;
    function firstTrue
      input Boolean b[:];
      output Integer index;
    algorithm
      index := 0;
      for i in 1:size(b, 1) loop
        if b[i] then
          index := i;
          return;
        end if;
      end for;
    end firstTrue;
    function untilAbove
      input Real u;
      output Real y = 0;
    algorithm
      for i in 1:3 loop
        if u < i then
          break;
        end if;
        y := y + i;
      end for;
    end untilAbove;
    model M
      Real z;
      Integer j;
      Integer k = firstTrue({time > 1, time > 2, time > 0.5});
      Real w = untilAbove(time);
    equation
      (z, j) = interp({0, 1, 2}, {0, 1, 4}, time, 2);
    end M;)";
  const std::string s = flat(src);
  // Forward from i = 2 (time >= 1): the loop's test `2 < 3 and time >= 1` is
  // known on that way and not asked again; backward to i = 1 otherwise, where
  // the backward loop's `time < 1` is known from the `if`.
  CHECK(contains(s, "z = if time >= 1 then 1 + (4 - 1) * (time - 1) / (2 - 1) else 0 + (1 - 0) * (time - 0) / (1 - 0);"));
  CHECK(contains(s, "j = if time >= 1 then 2 else 1;"));
  // Integer outputs keep their events. Where time > 1 is false, time > 2 is
  // too (the bounds of `time` on that way).
  CHECK(contains(s, "k = if time > 1 then 1 else if time > 0.5 then 3 else 0;"));
  // A Real output: no events, and the decisions still read the relations' bounds.
  CHECK(contains(s, "w = if noEvent(time < 1) then 0 else if noEvent(time < 2) then 1 else if noEvent(time < 3) then 3 else 6;"));
}

TEST_CASE("a function's array indexed by a varying Integer selects by an if-expression", "[msl][functions]") {
  // The MSL's TimeTable indexes its table by the row an earlier event found.
  const std::string s = flat(R"(
    function pick
      input Real a[:];
      input Integer i;
      output Real y;
    protected
      Integer k;
    algorithm
      k := i;
      y := a[k] + a[2];
    end pick;
    model M
      Integer j = if time > 1 then 2 else 1;
      Real z = pick({10, 20, 30}, j);
    end M;)");
  CHECK(contains(s, "z = (if j == 1 then 10 else if j == 2 then 20 else 30) + 20;"));
}

TEST_CASE("a while-loop from a varying row ends where its subscripts leave the table", "[msl][functions]") {
  // The MSL's TimeTable: `next := last; while next < nrow and t >= table[next, 1]`.
  // table[next] bounds next to 1..3 on every way, so `j + 2 < 3` is false and
  // there are three ways through, not kMaxDecisions.
  const std::string s = flat(R"(
    function rowAfter
      input Real tab[:];
      input Real t;
      input Integer last;
      output Integer next;
    protected
      Integer n = size(tab, 1);
    algorithm
      next := last;
      while next < n and t >= tab[next] loop
        next := next + 1;
      end while;
    end rowAfter;
    model M
      Integer j = if time > 5 then 2 else 1;
      Integer k = rowAfter({0, 1, 2}, time, j);
    end M;)");
  CHECK(contains(s, "k = if j < 3 and time >= (if j == 1 then 0 else if j == 2 then 1 else 2) then "
                    "if j + 1 < 3 and time >= (if j + 1 == 1 then 0 else if j + 1 == 2 then 1 else 2) then "
                    "j + 1 + 1 else j + 1 else j;"));
  // A guard before the subscript (`j <= n and x > a[j]`): a[j] is evaluated only
  // where the guard holds, so the way out at j = n + 1 stays (k = 4 for time > 2).
  const std::string g = flat(R"(
    function countAbove
      input Real a[:];
      input Real x;
      input Integer first;
      output Integer j;
    algorithm
      j := first;
      while j <= size(a, 1) and x > a[j] loop
        j := j + 1;
      end while;
    end countAbove;
    model G
      Integer j0 = if time > 5 then 2 else 1;
      Integer k = countAbove({0, 1, 2}, time, j0);
    end G;)");
  CHECK(contains(g, "then j0 + 1 + 1 + 1 else j0 + 1 + 1 else j0 + 1 else j0;"));
}

TEST_CASE("a built-in of a size parameter decides a function's branch now", "[msl][functions]") {
  // MultiPhase's symmetricOrientation(m): `if mod(m, 2) == 0` on the phase
  // count that sizes its output. Both branches ran before, and the even one
  // indexed past the odd size (subscript 2 out of bounds 1..1).
  const std::string s = flat(R"(
    function halves
      input Integer n;
      output Real y[n];
    algorithm
      if mod(n, 2) == 0 then
        if n == 2 then
          y[1] := 1;
          y[2] := 2;
        else
          y[1:integer(n/2)] := halves(integer(n/2));
          y[integer(n/2) + 1:n] := halves(integer(n/2)) + fill(10, integer(n/2));
        end if;
      else
        y := {k for k in 1:n};
      end if;
    end halves;
    model M
      parameter Integer n = 3;
      parameter Integer m = 4;
      parameter Real y[n] = halves(n);
      parameter Real z[m] = halves(m);
    end M;)");
  CHECK(contains(s, "parameter Real `y[3]` = 3;"));
  CHECK(contains(s, "parameter Real `z[2]` = 2;"));
  CHECK(contains(s, "parameter Real `z[4]` = 12;"));
}

TEST_CASE("algorithm sections of models that assign each variable once are equations", "[msl][algorithm]") {
  const char *src = R"(
    model Alg
      parameter Real period = 0.5;
      Integer count;
      Real T_start;
      Real y;
      Real z;
    initial algorithm
      count := integer(time / period);
      T_start := count * period;
    algorithm
      when integer(time / period) > pre(count) then
        count := pre(count) + 1;
        T_start := time;
      end when;
      y := time - T_start;
      z := 2 * y;
    end Alg;)";
  const std::string s = flat(src);
  CHECK(contains(s, "  when integer(time / period) > pre(count) then\n    count = pre(count) + 1;\n"
                    "    T_start = time;\n  end when;\n  y = time - T_start;\n  z = 2 * y;\n"));
  CHECK(contains(s, "initial equation\n  count = integer(time / period);\n  T_start = count * period;\n"));
}

namespace {
/// The flat text of `model A ... end A;` with `decls` and the algorithm `body`.
std::string algorithm_flat(const std::string &decls, const std::string &body, const std::string &before = "") {
  return flat(before + "model A\n" + decls + "\nalgorithm\n" + body + "\nend A;\n", "A");
}
} // namespace

TEST_CASE("algorithm sections: reassignment and reads before reassignment", "[msl][algorithm]") {
  const std::string s = algorithm_flat("  Real y, z;", "  y := 1; y := y + time; z := y; y := 2 * y;");
  CHECK(contains(s, "  y = 2 * (1 + time);\n  z = 1 + time;\n"));
  // Read before the section assigns it: the start value (continuous), pre() (discrete).
  const std::string t = algorithm_flat("  Real y(start = 3), z;\n  Integer n;", "  z := y; y := time; n := n + 1;");
  CHECK(contains(t, "  z = 3;\n  y = time;\n  n = pre(n) + 1;\n"));
}

TEST_CASE("algorithm sections: if on a varying condition joins the branches' values", "[msl][algorithm]") {
  // Branches assigning different variables; a variable one branch leaves keeps its value before the if.
  const std::string s = algorithm_flat("  Real u = sin(time), w, s(start = 5);",
                                       "  w := 0;\n  if u > 0.5 then\n    w := 1;\n  elseif u > 0 then\n    s := 2 * u;\n"
                                       "  else\n    s := -u;\n    w := 2;\n  end if;");
  CHECK(contains(s, "  w = if u > 0.5 then 1 else if u > 0 then 0 else 2;\n"));
  CHECK(contains(s, "  s = if u > 0.5 then 5 else if u > 0 then 2 * u else -u;\n"));
  // Nested ifs; a parameter condition picks its branch now.
  const std::string n = algorithm_flat("  parameter Boolean big = false;\n  Real y;",
                                       "  if big then\n    y := 10;\n  else\n    if time > 1 then\n"
                                       "      if time > 2 then y := 2; else y := 1; end if;\n    else\n      y := 0;\n"
                                       "    end if;\n  end if;");
  CHECK(contains(n, "  y = if time > 1 then if time > 2 then 2 else 1 else 0;\n"));
}

TEST_CASE("algorithm sections: for-loops unroll, accumulators and array elements", "[msl][algorithm]") {
  const std::string s = algorithm_flat("  parameter Integer n = 3;\n  Real acc, v[n];",
                                       "  acc := 0;\n  for i in 1:n loop\n    acc := acc + i * time;\n    v[i] := acc;\n"
                                       "  end for;");
  CHECK(contains(s, "  acc = 0 + 1 * time + 2 * time + 3 * time;\n"));
  CHECK(contains(s, "  `v[2]` = 0 + 1 * time + 2 * time;\n"));
  // A while-loop on a condition known now, with break.
  const std::string w = algorithm_flat("  Real y;\n  Integer k;",
                                       "  k := 1;\n  while k < 10 loop\n    k := 2 * k;\n    if k > 5 then break; end if;\n"
                                       "  end while;\n  y := k * time;");
  CHECK(contains(w, "  y = 8 * time;\n"));
}

TEST_CASE("algorithm sections: several outputs and default arguments of functions", "[msl][algorithm]") {
  const char *fn = R"(
    function f
      input Real u;
      input Real gain = 2;
      output Real y1;
      output Real y2;
    algorithm
      y1 := gain * u;
      y2 := y1 + 1;
    end f;
  )";
  const std::string s = algorithm_flat("  Real a, b, c;", "  (a, b) := f(time);\n  (, c) := f(a, 3);", fn);
  CHECK(contains(s, "  a = 2 * time;\n  b = 2 * time + 1;\n  c = 3 * (2 * time) + 1;\n"));
}

TEST_CASE("algorithm sections: when statements become when-clauses", "[msl][algorithm]") {
  const std::string s = algorithm_flat(
      "  parameter Integer n = 2;\n  Integer count(start = 0, fixed = true), bits[n];\n  Real y;",
      "  when time > 0.5 then\n    count := count + 1;\n    if count > 2 then count := 0; end if;\n"
      "    for i in 1:n loop\n      bits[i] := mod(count, 2);\n    end for;\n"
      "  elsewhen time > 2 then\n    count := 5;\n  end when;\n  y := count * time;");
  CHECK(contains(s, "  when time > 0.5 then\n    count = if pre(count) + 1 > 2 then 0 else pre(count) + 1;\n"
                    "    `bits[1]` = mod(if pre(count) + 1 > 2 then 0 else pre(count) + 1, 2);\n"));
  CHECK(contains(s, "  elsewhen time > 2 then\n    count = 5;\n    `bits[1]` = pre(`bits[1]`);\n"));
  CHECK(contains(s, "  y = count * time;\n"));
}

TEST_CASE("algorithm sections: what cannot be flattened gets a diagnostic", "[msl][algorithm]") {
  struct Case {
    const char *body, *message;
  };
  for (const Case &c : {Case{"y := 0; while y < time loop y := y + 1; end while;", "a while-loop whose condition varies in time"},
                        Case{"y := 1; return;", "'return' is only allowed in functions"},
                        Case{"if time > 1 then when time > 2 then y := 1; end when; end if;",
                             "a when-statement must be at the top of the algorithm section"},
                        Case{"y := time; when time > 1 then y := 2; end when;",
                             "is assigned both inside and outside a when-statement"},
                        Case{"y := 1; if time > 1 then break; end if;",
                             "'break' under a condition that varies in time, outside a loop"}}) {
    Compiled r = compile_text(std::string("model A\n  Real y;\nalgorithm\n  ") + c.body + "\nend A;\n");
    INFO(c.body);
    CHECK_FALSE(r.ok());
    CHECK(contains(r.diagnostics, c.message));
  }
}

TEST_CASE("a base class named by an import of the class itself", "[msl][lookup]") {
  const char *src = R"(
    package P
      package Interfaces
        partial model Rigid
          Real s(start = 1, fixed = true);
        end Rigid;
      end Interfaces;
      package Components
        model Mass
          import P.Interfaces.Rigid;
          extends Rigid(s(start = 2));
        equation
          der(s) = -s;
        end Mass;
      end Components;
    end P;
    model Use
      P.Components.Mass m;
    end Use;)";
  CHECK(contains(flat(src), "Real `m.s`(start = 2, fixed = true);"));
}

TEST_CASE("ModelicaStrings' substring and length are evaluated on constant strings", "[msl]") {
  // As the MSL's transformers: a connection letter taken from a String
  // constant, passed as a String parameter, and compared.
  const std::string lib = R"(
    function substring
      input String string; input Integer startIndex; input Integer endIndex;
      output String result;
      external "C" result = ModelicaStrings_substring(string, startIndex, endIndex);
    end substring;
    function length
      input String string; output Integer result;
      external "C" result = ModelicaStrings_length(string);
    end length;
    record Data
      parameter String C1 = "Y";
      parameter Real n = if C1 == "D" then 1 else sqrt(3);
    end Data;)";
  const std::string text = lib + R"(
    model Transformer
      constant String VectorGroup = "Dy05";
      parameter Data data(C1 = substring(VectorGroup, 1, 1));
      parameter String C2 = substring(VectorGroup, 2, 2);
      parameter Real star = if C2 == "y" then 1 else 0;
      parameter Integer len = length(VectorGroup + "x");
      parameter Integer one = length(substring(VectorGroup, 3, -999));
    end Transformer;)";
  CHECK(value(text, "data.n") == 1.0);
  CHECK(value(text, "star") == 1.0);
  CHECK(value(text, "len") == 5.0);
  CHECK(value(text, "one") == 1.0);
  // An index outside the string, or an end before the start, is an error at the index.
  const Compiled bad = compile_text(lib + R"(
    model Bad
      constant String g = "Yy00";
      parameter Real x = if substring(g, 2, 7) == "y" then 1 else 0;
    end Bad;)");
  CHECK_FALSE(bad.ok());
  CHECK(contains(bad.diagnostics, "end index 7 is beyond the string \"Yy00\" (length 4)"));
  const Compiled backwards = compile_text(lib + R"(
    model Backwards
      parameter String s = substring("Yy00", 3, 2);
    end Backwards;)");
  CHECK_FALSE(backwards.ok());
  CHECK(contains(backwards.diagnostics, "end index 2 is before the start index 3"));
}

TEST_CASE("each belongs to the arrays of the component whose modifier holds it", "[msl]") {
  // MLS 7.2.5. The MSL writes `TransferFunction transferFunction[na](each b =
  // {...})` (b unsized) and `SineVoltage sinevoltage(each V = fill(v, m))` on
  // a scalar component, where `each` has nothing to apply to: both used to
  // bind the whole array to each element of b or V.
  Compiled c = compile_text(R"(
    model C
      parameter Real a[3];
      parameter Real b[:] = {0};
      Real x(start = 0, fixed = true);
    equation
      der(x) = a[1] + a[2] + a[3] + sum(b);
    end C;
    model D
      C e[2];
    end D;
    model B
      C c[2](each a = {1, 2, 3}, each b = {10, 20});
      C d(each a = {4, 5, 6});
      D dd[2](e(each a = {7, 8, 9}));
    end B;)", "B");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string flat = c.model->print();
  CHECK(contains(flat, "`c[2].a[3]` = 3;"));
  CHECK(contains(flat, "`c[2].b[1]` = 10;"));
  CHECK(contains(flat, "`c[2].b[2]` = 20;"));
  CHECK(contains(flat, "`d.a[2]` = 5;"));
  CHECK(contains(flat, "`dd[2].e[1].a[3]` = 9;"));
}

TEST_CASE("an empty range subscript selects nothing", "[msl]") {
  // `x[2:n]` with n = 1 (the MSL's PowerConverters control with one phase
  // pair): it used to read past the selection and crash.
  Compiled c = compile_text(R"(
    model E
      parameter Integer n = 1;
      Real x[n](each start = 1, each fixed = true);
      Real y;
    equation
      der(x) = -x;
      y = sum(x[2:n]) + x[1];
    end E;)", "E");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  CHECK(contains(c.model->print(), "y = 0. + `x[1]`;"));
}

TEST_CASE("cardinality() counts a connector's connect() occurrences, inside and outside", "[msl]") {
  // MLS 3.7.2.3; the MSL's StateGraph decides with it whether a step's port
  // is connected (`if cardinality(inPort[i]) == 0 then ...`).
  Compiled c = compile_text(R"(
    connector Pin
      Real v;
      flow Real i;
    end Pin;
    model Source
      Pin p;
      Real n;
    equation
      p.v = 1;
      n = cardinality(p);
    end Source;
    model Load
      Pin p;
      Real n;
    equation
      p.i = p.v;
      n = cardinality(p);
    end Load;
    model Pair "p connected inside to a.p"
      Pin p;
      Load a;
      Real n;
    equation
      n = cardinality(p);
      connect(p, a.p);
    end Pair;
    model Top
      Source s;
      Load l[3];
      Pair q;
      Source t;
    equation
      for k in 1:2 loop
        connect(s.p, l[k].p);
      end for;
      connect(t.p, q.p);
    end Top;)", "Top");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string flat = c.model->print();
  INFO(flat);
  CHECK(contains(flat, "`s.n` = 2;"));
  CHECK(contains(flat, "`l[1].n` = 1;"));
  CHECK(contains(flat, "`l[3].n` = 0;"));  // not connected
  CHECK(contains(flat, "`q.n` = 2;"));     // once inside, once outside
  CHECK(contains(flat, "`q.a.n` = 1;"));
}

TEST_CASE("cardinality() in a binding is refused with a diagnostic", "[msl]") {
  Compiled c = compile_text(R"(
    connector Pin
      Real v;
      flow Real i;
    end Pin;
    model M
      Pin p;
      parameter Integer n = cardinality(p);
    equation
      p.v = n;
    end M;)", "M");
  CHECK_FALSE(c.ok());
  CHECK(contains(c.diagnostics, "cardinality() is supported in equations"));
}

TEST_CASE("an if-expression whose condition is literal flattens only the branch it takes", "[msl]") {
  // The MSL's StateGraph: `inPort[i].occupied = if i == 1 then localActive
  // else inPort[i-1].occupied or ...` in a for-loop; for i = 1 the other
  // branch's inPort[0] is out of bounds and must not be flattened.
  Compiled c = compile_text(R"(
    model L
      parameter Integer n = 2;
      Real x[n](each start = 1, each fixed = true);
      Real y[n];
    equation
      der(x) = -x;
      for i in 1:n loop
        y[i] = if i == 1 then x[1] else y[i - 1] + x[i];
      end for;
    end L;)", "L");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string flat = c.model->print();
  INFO(flat);
  CHECK(contains(flat, "`y[1]` = `x[1]`;"));
  CHECK(contains(flat, "`y[2]` = `y[1]` + `x[2]`;"));
}
