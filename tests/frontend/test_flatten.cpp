// Flattening semantics on small models, against the exact flat text.
#include "compile.hpp"

#include <catch2/catch.hpp>

using namespace mo::test;

namespace {
std::string flat(const std::string &text, const std::string &cls = "") {
  Compiled c = compile_text(text, cls);
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  return c.model->print();
}
} // namespace

TEST_CASE("extends with modifiers, parameters in dependency order", "[flatten]") {
  const char *src = R"(
    partial model Base
      parameter Real k = 1;
      Real x(start = k);
    equation
      der(x) = -k * x;
    end Base;
    model M
      extends Base(k = 2 * c);
      parameter Real c = 3 "gain";
    end M;)";
  CHECK(flat(src) == R"(class M
  parameter Real c = 3 "gain";
  parameter Real k = 2 * c;
  Real x(start = k);
equation
  der(x) = -k * x;
end M;
)");
}

TEST_CASE("arrays, for-equations and array bindings scalarise", "[flatten]") {
  const char *src = R"(
    model A
      parameter Integer n = 3;
      parameter Real w[n] = {1, 2, 3};
      Real x[n];
    equation
      for i in 1:n loop
        der(x[i]) = -w[i] * x[i];
      end for;
    end A;)";
  std::string s = flat(src);
  CHECK(s.find("parameter Real `w[2]` = 2;") != std::string::npos);
  CHECK(s.find("der(`x[3]`) = -`w[3]` * `x[3]`;") != std::string::npos);
  Compiled c = compile_text(src);
  REQUIRE(c.ok());
  CHECK(c.model->variables.size() == 7);
  CHECK(c.model->variables[c.model->find("w[3]")].value == 3.0);
}

TEST_CASE("connect: potentials equal, flows sum to zero, unconnected flows zero", "[flatten]") {
  const char *src = R"(
    connector Pin
      Real v;
      flow Real i;
    end Pin;
    model R
      Pin p, n;
      parameter Real r = 1;
    equation
      r * p.i = p.v - n.v;
      p.i + n.i = 0;
    end R;
    model Two
      R a, b;
      Pin outer_pin;
    equation
      connect(a.n, b.p);
      connect(outer_pin, a.p);
    end Two;)";
  std::string s = flat(src, "Two");
  CHECK(s.find("`a.n.i` + `b.p.i` = 0.;") != std::string::npos);
  CHECK(s.find("`a.n.v` = `b.p.v`;") != std::string::npos);
  // outer_pin is seen from outside in Two's connect: its flow enters with −;
  // its own inside element is unconnected, so its flow is zero.
  CHECK(s.find("-`outer_pin.i` + `a.p.i` = 0.;") != std::string::npos);
  CHECK(s.find("`outer_pin.i` = 0.;") != std::string::npos);
  CHECK(s.find("`b.n.i` = 0.;") != std::string::npos);
}

TEST_CASE("if-equations on parameters are decided - when-clauses and reinit are kept", "[flatten]") {
  const char *src = R"(
    model Ball
      parameter Boolean bounce = true;
      parameter Real e = 0.8;
      Real h(start = 1, fixed = true), v;
    equation
      der(h) = v;
      if bounce then
        der(v) = -9.81;
      else
        der(v) = 0;
      end if;
      when h < 0 then
        reinit(v, -e * pre(v));
      end when;
    end Ball;)";
  CHECK(flat(src) == R"(class Ball
  parameter Boolean bounce = true;
  parameter Real e = 0.8;
  Real h(start = 1, fixed = true);
  Real v;
equation
  der(h) = v;
  der(v) = -9.81;
  when h < 0 then
    reinit(v, -e * pre(v));
  end when;
end Ball;
)");
}

TEST_CASE("Optimica: objective, bounds, free parameters and point constraints", "[flatten][optimica]") {
  const char *src = R"(
    model Plant
      parameter Real m = 1;
      input Real u;
      Real x(start = 0, fixed = true), v(start = 0, fixed = true);
    equation
      der(x) = v;
      m * der(v) = u;
    end Plant;
    optimization Move(objectiveIntegrand = u^2, startTime = 0, finalTime = 2)
      extends Plant(u(min = -5, max = 5, initialGuess = 0), m(free = true, min = 0.1));
    constraint
      x(finalTime) = 1;
      v(finalTime) = 0;
      x <= 1.2;
    end Move;)";
  Compiled c = compile_text(src, "Move");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  REQUIRE(c.model->optimization);
  CHECK(c.model->optimization->constraints.size() == 3);
  std::string s = c.model->print();
  CHECK(s.find("optimization Move(objectiveIntegrand = u^2, startTime = 0, finalTime = 2)") != std::string::npos);
  CHECK(s.find("parameter Real m(min = 0.1, free = true) = 1;") != std::string::npos);
  CHECK(s.find("input Real u(min = -5, max = 5, initialGuess = 0);") != std::string::npos);
  CHECK(s.find("  x(2) = 1;") != std::string::npos); // finalTime is substituted
  CHECK(s.find("  x <= 1.2;") != std::string::npos);
  // The flat problem reads back as the same problem.
  Compiled again = compile({{"again.mo", s}}, "Move");
  INFO(again.diagnostics);
  REQUIRE(again.ok());
  CHECK(again.model->print() == s);
}

TEST_CASE("packages, imports, short classes and constants resolve", "[flatten]") {
  const char *src = R"(
    package Lib
      constant Real pi = 3.14159;
      type Voltage = Real(unit = "V");
      package Sub
        model Src
          Voltage u;
        equation
          u = sin(2 * pi * time);
        end Src;
      end Sub;
    end Lib;
    model Top
      import Lib.Sub.Src;
      Src s;
      Real y = 2 * s.u;
    end Top;)";
  CHECK(flat(src, "Top") == R"(class Top
  Real `s.u`(unit = "V");
  Real y;
equation
  y = 2 * `s.u`;
  `s.u` = sin(2 * 3.14159 * time);
end Top;
)");
}

// MLS 5.3.1: built-in names are looked up like others, in the enclosing
// scopes first (the MSL's Matrices.integralExpT calls its own package's
// two-argument exp; ComplexMath.sin calls ComplexMath.exp).
TEST_CASE("a function named like a built-in in an enclosing scope is the one called", "[flatten]") {
  const char *src = R"(
    package Lib
      function sum "a scalar function named like the reduction"
        input Real x;
        output Real y = 2 * x;
      algorithm
      end sum;
      package Inner
        model Uses
          Real a = sum(time);
          Real b = abs(-time); // not shadowed: the built-in
        end Uses;
      end Inner;
      encapsulated model Sealed
        Real c = sum({time, 1}); // from an encapsulated class: the global scope
      end Sealed;
    end Lib;
    model Own
      function sin
        input String s;
        output Real r = 1.5;
      algorithm
      end sin;
      Real r = sin("abc");
      Lib.Inner.Uses u;
      Lib.Sealed v;
    end Own;)";
  CHECK(flat(src, "Own") == R"(class Own
  Real r;
  Real `u.a`;
  Real `u.b`;
  Real `v.c`;
equation
  r = 1.5;
  `u.a` = 2 * time;
  `u.b` = abs(-time);
  `v.c` = time + 1;
end Own;
)");
}

TEST_CASE("the AST dump (--emit ast) shows the parsed tree", "[parser]") {
  using namespace mo::frontend;
  SourceManager sm;
  DiagnosticEngine diags(sm);
  FileId id = sm.add("a.mo", "within P; model M \"doc\" parameter Real k(min = 0) = 1; equation k = k; end M;");
  auto sd = parse(id, sm, diags);
  REQUIRE(sd);
  CHECK(ast::dump(*sd) == "within P\nmodel M \"doc\"\n  component parameter Real k(min = 0) = 1\n  equation\n    k = k\n");
}

TEST_CASE("a repeated equation is counted once, with a warning at the repetition", "[flatten]") {
  const char *src = R"(model R
  Real delta(start = 0);
  Real d;
  input Real u;
equation
  delta = d;
  der(delta) = u - delta;
  d = delta;
end R;
)";
  Compiled c = compile_text(src);
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  CHECK(c.model->print().find("d = delta") == std::string::npos);
  CHECK(c.diagnostics.find("8:3: warning: this equation repeats an earlier one; it is counted once") !=
        std::string::npos);
  CHECK(c.diagnostics.find("6:3: note: the earlier equation") != std::string::npos);
  // Equations that differ are both kept (and then the model is unbalanced).
  Compiled other = compile_text("model S\n  Real x;\nequation\n  x = 1;\n  x = 2;\nend S;\n");
  CHECK(!other.ok());
  CHECK(other.diagnostics.find("unbalanced") != std::string::npos);
}

TEST_CASE("an if-equation inside a when-clause counts its variables in the balance", "[flatten]") {
  const char *src = R"(
model WhenIf
  discrete Real a(start = 0, fixed = true), b(start = 0, fixed = true);
equation
  when time > pre(b) then
    a = time;
    if a < 10 then b = a; else b = 10; end if;
  end when;
end WhenIf;
)";
  Compiled c = compile_text(src);
  INFO(c.diagnostics);
  CHECK(c.ok()); // 2 equations for 2 unknowns; before: 1 for 2
}

TEST_CASE("A.B whose nearest A lacks B is looked up further out, as JModelica does, with a warning", "[flatten]") {
  // JModelica's Optimica examples (DoublePendulum.mop) are written so: inside
  // package Pend, `Pend.Pend` names the package's model Pend, and Modelica's
  // lookup (§5.3.2) stops at the nearest Pend, the model, which has no Pend.
  const Source lib{"Pend.mo", "package Pend\n  model Pend\n    Real x(start = 1, fixed = true);\n  equation\n"
                              "    der(x) = -x;\n  end Pend;\n  model Feedback\n    Pend p;\n  end Feedback;\nend Pend;\n"};
  const Source opt{"Opt.mo", "within Pend;\nmodel Opt\n  Pend.Pend p;\nend Opt;\n"};
  const Compiled c = compile({lib, opt}, "Pend.Opt");
  REQUIRE(c.ok());
  CHECK(c.model->variables.size() == 1);
  CHECK_THAT(c.diagnostics, Catch::Contains("Opt.mo:3:3: warning: 'Pend.Pend': the nearest 'Pend' is 'Pend.Pend', "
                                            "which has no element 'Pend'"));
  CHECK_THAT(c.diagnostics, Catch::Contains("the 'Pend' further out, 'Pend', is taken"));
  // Modelica's own lookup finds the model: no warning for Feedback.
  const Compiled f = compile({lib}, "Pend.Feedback");
  REQUIRE(f.ok());
  CHECK(f.diagnostics.empty());
  // No A further out has a B either: still an unknown class.
  const Compiled bad = compile({lib, {"Bad.mo", "within Pend;\nmodel Bad\n  Pend.Nothing p;\nend Bad;\n"}}, "Pend.Bad");
  CHECK_FALSE(bad.ok());
  CHECK_THAT(bad.diagnostics, Catch::Contains("unknown class 'Pend.Nothing'"));
}
