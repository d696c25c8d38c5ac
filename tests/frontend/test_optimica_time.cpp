// Optimica's startTime/finalTime as JModelica writes them (issue 12.2): a free
// final time with or without a value becomes the free parameter `finalTime`
// that the objective and the constraints refer to; the defaults 0 and 1 are
// usable without a header value; a free startTime and unknown attributes are
// errors with a source position; an optimization class extending another
// inherits the attributes it does not set.
#include "compile.hpp"

#include <catch2/catch.hpp>

using namespace mo::test;

namespace {

const char *kPlant = R"(
    model Plant
      input Real u(min = -1, max = 1);
      Real x(start = 0, fixed = true), v(start = 0, fixed = true);
    equation
      der(x) = v;
      der(v) = u;
    end Plant;
)";

Compiled study(const std::string &header, const std::string &constraints = "x(finalTime) = 1;") {
  return compile_text(std::string(kPlant) + "optimization Opt(" + header + ")\n  extends Plant;\nconstraint\n  " +
                          constraints + "\nend Opt;\n",
                      "Opt");
}

} // namespace

TEST_CASE("Optimica: finalTime(free = true) without a value is a free parameter", "[flatten][optimica]") {
  Compiled c = study("objective = finalTime, finalTime(free = true, min = 0.5, max = 9, initialGuess = 3)");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const auto &opt = *c.model->optimization;
  REQUIRE(opt.free_final_time >= 0);
  const auto &tf = c.model->variables[static_cast<std::size_t>(opt.free_final_time)];
  CHECK(tf.name == "finalTime");
  CHECK(tf.variability == mo::frontend::ast::Variability::Parameter);
  CHECK(tf.value == 3.0);
  REQUIRE(tf.attr.free);
  REQUIRE(tf.attr.min);
  CHECK(tf.attr.min->number == 0.5);
  // The objective and the point constraint refer to the parameter.
  REQUIRE(opt.objective);
  CHECK(opt.objective->var == opt.free_final_time);
  REQUIRE(opt.constraints.size() == 1);
  CHECK(opt.constraints[0].lhs->args[0]->var == opt.free_final_time);
  // Printed back as the header attribute, and flattened again to the same text.
  const std::string s = c.model->print();
  CHECK(s.find("optimization Opt(objective = finalTime, finalTime(free = true, min = 0.5, max = 9, "
               "initialGuess = 3))") != std::string::npos);
  Compiled again = compile({{"again.mo", s}}, "Opt");
  INFO(again.diagnostics);
  REQUIRE(again.ok());
  CHECK(again.model->print() == s);
}

TEST_CASE("Optimica: finalTime(free = true) = value starts from the value", "[flatten][optimica]") {
  Compiled c = study("objective = finalTime, finalTime(free = true, min = 0.5) = 4");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const auto &opt = *c.model->optimization;
  REQUIRE(opt.free_final_time >= 0);
  CHECK(c.model->variables[static_cast<std::size_t>(opt.free_final_time)].value == 4.0);
  // free = false keeps the final time fixed.
  Compiled fixed = study("objective = x(finalTime), finalTime(free = false) = 2");
  INFO(fixed.diagnostics);
  REQUIRE(fixed.ok());
  CHECK(fixed.model->optimization->free_final_time == -1);
  CHECK(fixed.model->print().find("x(2) = 1;") != std::string::npos);
}

TEST_CASE("Optimica: startTime and finalTime have their defaults in expressions", "[flatten][optimica]") {
  Compiled c = study("objective = x(finalTime)", "x(startTime) = 0;\n  v <= finalTime;");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string s = c.model->print();
  CHECK(s.find("x(0.) = 0;") != std::string::npos);
  CHECK(s.find("v <= 1.;") != std::string::npos);
}

TEST_CASE("Optimica: a free startTime and unknown time attributes are errors", "[flatten][optimica]") {
  Compiled c = study("objective = finalTime, startTime(free = true), finalTime = 2");
  CHECK_FALSE(c.ok());
  CHECK(c.diagnostics.find("error: a free startTime is not supported (only finalTime may be free)") !=
        std::string::npos);
  c = study("objective = finalTime, finalTime(free = true, nominal = 2)");
  CHECK_FALSE(c.ok());
  CHECK(c.diagnostics.find("error: 'nominal' is not an attribute of finalTime") != std::string::npos);
  c = compile_text(std::string(kPlant) +
                       "optimization Opt(objective = finalTime, finalTime(free = true))\n"
                       "  extends Plant;\n  Real finalTime = 1;\nend Opt;\n",
                   "Opt");
  CHECK_FALSE(c.ok());
  CHECK(c.diagnostics.find("a variable of the model already has") != std::string::npos);
}

TEST_CASE("Optimica: an optimization class inherits the class attributes of the one it extends",
          "[flatten][optimica]") {
  // A study built on another tool's optimization class (a wrapper adding an
  // objective) keeps its horizon; attributes the derived class sets win.
  const std::string base = std::string(kPlant) +
                           "optimization Base(objective = x(finalTime), startTime = 0.5, finalTime = 3)\n"
                           "  extends Plant;\nconstraint\n  v <= finalTime;\nend Base;\n";
  Compiled c = compile_text(base + "optimization Derived(objectiveIntegrand = u^2)\n  extends Base;\nend Derived;\n",
                            "Derived");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string s = c.model->print();
  CHECK(s.find("optimization Derived(objective = x(3), objectiveIntegrand = u^2, startTime = 0.5, "
               "finalTime = 3)") != std::string::npos);
  CHECK(s.find("v <= 3;") != std::string::npos);
  Compiled shorter = compile_text(base + "optimization Shorter(finalTime = 2)\n  extends Base;\nend Shorter;\n",
                                  "Shorter");
  INFO(shorter.diagnostics);
  REQUIRE(shorter.ok());
  CHECK(shorter.model->print().find("optimization Shorter(objective = x(2), startTime = 0.5, finalTime = 2)") !=
        std::string::npos);
  // A free final time is inherited too.
  Compiled free = compile_text(std::string(kPlant) +
                                   "optimization Fast(objective = finalTime, finalTime(free = true, min = 0.5))\n"
                                   "  extends Plant;\nend Fast;\n"
                                   "optimization Faster(objectiveIntegrand = u^2)\n  extends Fast;\nend Faster;\n",
                               "Faster");
  INFO(free.diagnostics);
  REQUIRE(free.ok());
  CHECK(free.model->optimization->free_final_time >= 0);
}
