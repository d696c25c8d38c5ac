// Issue 10 end to end, from .mo text: an Xcos-style free input driven by
// --input or left at 0, a discrete variable set by two when-clauses, a model
// without states, and a state that must not move through a scaled alias.
// Each against its analytic solution. Models in data/xcos/.
#include "e2e/cli.hpp"
#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

const std::string kXcos = kData + "xcos/";

}  // namespace

TEST_CASE("xcos: a free input of a flat file is a model input", "[e2e][xcos]") {
  auto model = compiled_model("e2e_xcos_free_input", {{kXcos + "FreeInput_imf.mo", "", {}, true}, {}});
  const auto& info = model->info();
  REQUIRE(info.inputs.size() == 1);
  CHECK(info.inputs[0].name == "InPutPort1.vi");
  std::vector<std::unique_ptr<runtime::InputSignal>> u;
  u.push_back(runtime::constant_input(2.0));
  const auto r = runtime::simulate(*model, runtime::Inputs(std::move(u)), info.default_parameters(),
                                   runtime::OutputGrid::uniform(0, 2, 20), tight());
  REQUIRE(r.ok());
  const auto x = column(r.trajectory, "x");
  for (std::size_t k = 0; k < x.size(); ++k)  // k x' = -k x + u, x(0) = 0, k = 2, u = 2
    CHECK(x[k] == Approx(1 - std::exp(-2 * r.trajectory.times()[k])).margin(1e-8));
}

TEST_CASE("xcos: morun drives a free input, or warns and uses 0", "[e2e][xcos][morun]") {
  const fs::path dir = scratch("xcos_free_input");
  const std::string model = quoted(kXcos + "FreeInput_imf.mo") + " --stop-time 1 -o " + quoted(dir.string());
  const Run driven = morun(model + " --input InPutPort1.vi=const:2", dir);
  INFO(driven.err);
  CHECK(driven.status == 0);
  CHECK(driven.err.find("undriven") == std::string::npos);
  const Run undriven = morun(model, dir);
  INFO(undriven.err);
  CHECK(undriven.status == 0);
  CHECK(undriven.err.find("warning: undriven input 'InPutPort1.vi' set to 0") != std::string::npos);
}

TEST_CASE("xcos: a variable set by two when-clauses keeps its value between them", "[e2e][xcos][events]") {
  auto model = compiled_model("e2e_xcos_two_whens", {{kXcos + "TwoWhens.mo", "", {}, true}, {}});
  const auto r = runtime::simulate(*model, runtime::Inputs{}, model->info().default_parameters(),
                                   runtime::OutputGrid::at({0, 0.5, 1.5, 2.25, 2.75, 3.5}), tight());
  REQUIRE(r.ok());
  const auto x = column(r.trajectory, "x");
  const std::vector<double> triangle{0, 0.5, 0.5, 0.25, 0.75, 0.5};  // up to 1 at t = 1, down to 0 at t = 2, ...
  for (std::size_t k = 0; k < x.size(); ++k) CHECK(x[k] == Approx(triangle[k]).margin(1e-6));
}

TEST_CASE("xcos: a model without states simulates, with its events", "[e2e][xcos]") {
  auto model = compiled_model("e2e_xcos_resistive", {{kXcos + "Resistive.mo", "", {}, true}, {}});
  REQUIRE(model->info().states.empty());
  const auto r = runtime::simulate(*model, runtime::Inputs{}, model->info().default_parameters(),
                                   runtime::OutputGrid::uniform(0, 2, 40), tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto i = column(r.trajectory, "i"), w = column(r.trajectory, "w");
  for (std::size_t k = 0; k < i.size(); ++k) {
    const double t = r.trajectory.times()[k];
    CHECK(i[k] == Approx(10 * std::sin(t) / (t > 0.5 ? 2.0 : 5.0)).margin(1e-9));
    CHECK(w[k] * w[k] * w[k] + w[k] == Approx(i[k]).margin(1e-8));
  }
}

TEST_CASE("xcos: a capacitor voltage stays the state through a scaled alias", "[e2e][xcos]") {
  auto model = compiled_model("e2e_xcos_scaled_capacitor", {{kXcos + "ScaledCapacitor.mo", "", {}, true}, {}});
  REQUIRE(model->info().states.size() == 1);
  CHECK(model->info().states[0].name == "vc");
  const auto r = runtime::simulate(*model, runtime::Inputs{}, model->info().default_parameters(),
                                   runtime::OutputGrid::uniform(0, 2, 20), tight());
  REQUIRE(r.ok());
  const auto vc = column(r.trajectory, "vc");
  for (std::size_t k = 0; k < vc.size(); ++k)  // vc(0) = 0, RC = 1
    CHECK(vc[k] == Approx(5 * (1 - std::exp(-r.trajectory.times()[k]))).margin(1e-7));
}
