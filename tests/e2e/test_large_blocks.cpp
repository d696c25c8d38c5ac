// A linear block of 40 unknowns (sparse LU, generated_support.hpp) in a
// simulation with sensitivities: the resistor ladder of data/Ladder.mo
// against its closed form, u = exp(-t / (C Req)), and du/dRs.
#include <cmath>

#include "e2e/support.hpp"
#include "mo/runtime/generated_support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

/// Z_1 of the ladder and dZ_1/dRs, by the recursion from the last node.
std::pair<double, double> ladder_impedance(int n, double r, double rs) {
  double z = rs, dz = 1.0;
  for (int i = n - 1; i >= 1; --i) {
    const double a = r + z, s = rs + a;
    const double next = rs * a / s;
    dz = (a * s + rs * dz * s - rs * a * (1.0 + dz)) / (s * s);
    z = next;
  }
  return {z, dz};
}

}  // namespace

TEST_CASE("a linear block of 40 unknowns: closed form and sensitivity", "[e2e][blocks]") {
  auto model = compiled_model("e2e_ladder", {{kData + "Ladder.mo", "Ladder", {}, true}, {"Rs"}});
  const auto& info = model->info();
  REQUIRE(40 >= runtime::generated::kSparseBlockSize);
  const auto grid = runtime::OutputGrid::uniform(0, 2, 40);
  runtime::SimulationOptions o = tight();
  o.sensitivities.method = runtime::SensitivityMethod::model_states;
  const auto r = runtime::simulate(*model, {}, info.default_parameters(), grid, o);
  INFO(r.message);
  REQUIRE(r.ok());
  const auto u = column(r.trajectory, "u");
  const auto du = column(r.trajectory, "d(u)/d(Rs)");
  const auto [z1, dz1] = ladder_impedance(40, 1.0, 3.0);
  const double c = 0.5, req = 1.0 + z1;
  for (std::size_t i = 0; i < grid.times.size(); ++i) {
    const double t = grid.times[i], expected = std::exp(-t / (c * req));
    INFO("t = " << t);
    CHECK(u[i] == Approx(expected).margin(1e-7));
    CHECK(du[i] == Approx(expected * t / (c * req * req) * dz1).margin(1e-7));
  }
}
