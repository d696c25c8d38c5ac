// Untrusted names: quoted Modelica identifiers and comments that would break
// or hijack generated C++ if pasted verbatim. The code must compile and every
// name must come back byte for byte through info() and failure messages.
#include <catch2/catch.hpp>

#include "codegen/models.hpp"
#include "codegen/support.hpp"

using namespace mo;
using namespace mo::codegen::test;

namespace {

const std::vector<std::string> hostile = {
    "'\"); system(\"rm -rf /\"); //'",
    "'*/ x'",
    "'a\nb\\c'",
    "'?\?=?\?/?\?''",
    "'\\\"\\\\\\n'",
    std::string("'nul\0byte'", 10),
    "'caf\xc3\xa9 \xe2\x88\x82x'",
    "'#include <cstdlib>'",
    "'}; } int main() { return 1; } namespace {'",
};

symbolic::OdeModel hostile_model() {
  OdeBuilder b("'model */ \" name'");
  auto& a = b.a;
  std::vector<Expr> states;
  for (std::size_t i = 0; i < hostile.size(); ++i)
    states.push_back(b.state(hostile[i], b.c(1.0 + static_cast<double>(i)), hostile[(i + 1) % hostile.size()],
                             hostile[(i + 2) % hostile.size()]));
  const Expr k = b.parameter(hostile[0] + "k", 0.5, "*/", "\"unit\" */ /*");
  const Expr u = b.input(hostile[1] + "u", "??", "\\");
  const Expr z1 = b.algebraic(hostile[2] + "z1"), z2 = b.algebraic(hostile[3] + "z2");
  const Expr d = b.discrete(hostile[4] + "d", 0.0);
  (void)d;
  for (std::size_t i = 0; i < hostile.size(); ++i) b.assign(b.der(i), a.mul(a.neg(k), states[i]));
  symbolic::EquationBlock blk;  // a singular block at k = 0, to see a hostile failure message
  blk.unknowns = {z1, z2};
  blk.offset = {a.neg(u), b.c(-1.0)};
  blk.jacobian = {{0, 0, k}, {1, 1, k}};
  blk.residuals = {a.sub(a.mul(k, z1), u), a.sub(a.mul(k, z2), b.c(1.0))};
  b.m.steps.emplace_back(blk);
  b.output(hostile[5] + "y", a.add(z1, z2), hostile[6], hostile[7]);
  return std::move(b.m);
}

}  // namespace

TEST_CASE("hostile names compile and round-trip through info()") {
  auto model = compiled("hostile", hostile_model);
  const runtime::ModelInfo& info = model->info();
  CHECK(info.name == "'model */ \" name'");
  REQUIRE(info.states.size() == hostile.size());
  for (std::size_t i = 0; i < hostile.size(); ++i) {
    CHECK(info.states[i].name == hostile[i]);
    CHECK(info.states[i].unit == hostile[(i + 1) % hostile.size()]);
    CHECK(info.states[i].description == hostile[(i + 2) % hostile.size()]);
    CHECK(info.states[i].start == 1.0 + static_cast<double>(i));
  }
  CHECK(info.states[5].name.size() == 10);  // the NUL byte survives
  CHECK(info.parameters.at(0).name == hostile[0] + "k");
  CHECK(info.parameters.at(0).unit == "*/");
  CHECK(info.parameters.at(0).description == "\"unit\" */ /*");
  CHECK(info.inputs.at(0).unit == "??");
  CHECK(info.inputs.at(0).description == "\\");
  CHECK(info.outputs.at(0).name == hostile[5] + "y");
  CHECK(info.discrete.at(0).name == hostile[4] + "d");

  std::vector<double> x(hostile.size(), 2.0), xdot(hostile.size()), y(1);
  model->rhs(0, x, std::vector<double>{3.0}, std::vector<double>{0.5}, xdot);
  CHECK(xdot[0] == -1.0);
  model->outputs(0, x, std::vector<double>{3.0}, std::vector<double>{0.5}, y);
  CHECK(y[0] == 8.0);
  model->outputs(0, x, std::vector<double>{3.0}, std::vector<double>{0.0}, y);
  CHECK(model->last_failure() ==
        "linear block 1 for " + hostile[2] + "z1, " + hostile[3] +
            "z2 at t = 0: the matrix is singular and its equations contradict each other");
}

TEST_CASE("hostile names become safe identifiers in the typed header") {
  symbolic::OdeModel m = hostile_model();
  const auto src = codegen::generate_cpp(m, {});
  const auto& header = src.files.at(0);
  REQUIRE(header.path == "mo_model.hpp");
  CHECK(header.text.find("system") != std::string::npos);
  CHECK(header.text.find("rm -rf") == std::string::npos);
  CHECK(header.text.find("int main") == std::string::npos);
  CHECK_THROWS_AS(codegen::generate_cpp(m, {.name = "bad name"}), std::invalid_argument);
}
