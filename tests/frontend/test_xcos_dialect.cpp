// The Xcos dialect rules of issue 10 at flattening (docs/xcos-dialect.md):
// inputs the equations leave free are inputs of the model, a variable set in
// several when-clauses counts once, and a when-assignment to a differentiated
// variable is a reinit.
#include "compile.hpp"

#include <catch2/catch.hpp>

using namespace mo::test;

namespace {

const mo::frontend::flat::Variable &variable(const Compiled &c, const std::string &name) {
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const auto k = c.model->find(name);
  INFO("variable " << name);
  REQUIRE(k >= 0);
  return c.model->variables[static_cast<std::size_t>(k)];
}

} // namespace

TEST_CASE("an input no equation defines is an input of the model, by structure", "[flatten][xcos]") {
  const Compiled c = compile_text(R"(
    class FreeInput_imf
      parameter Real `k` = 2.;
      Real `x`;
      Real `InPutPort1.vo`;
      input Real `InPutPort1.vi`;
      output Real `OutPutPort1.vo`;
    equation
      `InPutPort1.vi` = `InPutPort1.vo`;
      der(`x`) = ((- (`k` * `x`)) + `InPutPort1.vo`);
      `OutPutPort1.vo` = `x`;
    end FreeInput_imf;)");
  CHECK(variable(c, "InPutPort1.vi").top_level_input);
  CHECK_FALSE(variable(c, "InPutPort1.vo").top_level_input);
  CHECK(c.diagnostics.empty());
}

TEST_CASE("a connected input of a component stays an unknown", "[flatten][xcos]") {
  const Compiled c = compile_text(R"(
    block Gain
      input Real u;
      output Real y;
      parameter Real k = 2;
    equation
      y = k * u;
    end Gain;
    block Source
      output Real y;
    equation
      y = sin(time);
    end Source;
    block Port
      input Real vi;
      Real vo;
    equation
      vi = vo;
    end Port;
    model Top
      Source s;
      Gain g;
      Port p;
      Gain h;
    equation
      g.u = s.y;
      h.u = p.vo;
    end Top;)");
  CHECK_FALSE(variable(c, "g.u").top_level_input);
  // In the chain p.vi = p.vo = h.u one of the two inputs is free; the
  // matching decides which (docs/xcos-dialect.md), and the model is balanced.
  CHECK(variable(c, "h.u").top_level_input != variable(c, "p.vi").top_level_input);
  CHECK(c.diagnostics.empty());
}

TEST_CASE("a variable assigned in several when-clauses is one equation", "[flatten][xcos]") {
  const Compiled c = compile_text(R"(
    model TwoWhens
      Real x(start = 0, fixed = true);
      discrete Real up(start = 1);
    equation
      der(x) = if up > 0.5 then 1 else -1;
      when x > 1 then
        up = 0;
      end when;
      when x < 0 then
        up = 1;
      end when;
    end TwoWhens;)");
  INFO(c.diagnostics);
  CHECK(c.ok());
}

TEST_CASE("too many when-assigned variables is still unbalanced", "[flatten][xcos]") {
  const Compiled c = compile_text(R"(
    model Over
      Real x(start = 0);
      discrete Real a, b;
    equation
      der(x) = 1;
      a = 2;
      when x > 1 then
        a = 0;
        b = 1;
      end when;
    end Over;)");
  CHECK_FALSE(c.ok());
  CHECK(c.diagnostics.find("4 equations for 3 unknowns") != std::string::npos);
}

TEST_CASE("a when-assignment to a differentiated variable is a reinit", "[flatten][xcos]") {
  const Compiled c = compile_text(R"(
    class Trapezoid_imf
      parameter Real `period` = 1.;
      Real `T0`;
      Real `y`;
    equation
      der(`T0`) = 0.;
      `y` = (time - `T0`);
    when (time > (`T0` + `period`)) then
      `T0` = time;
    end when;
    end Trapezoid_imf;)");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  CHECK(c.model->print().find("reinit(T0, time);") != std::string::npos);
}
