// The MSL's ComplexBlocks (tests/e2e/data/MslComplexBlocks.mo): Complex signals
// and Complex arithmetic through the operator record Complex (MLS 14,
// frontend/src/flatten_operators.cpp), against closed forms.
#include <cmath>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

// With d = 1/sqrt(2): |H(jw)|^2 = 1 / ((1 - w^2)^2 + 2 w^2) = 1 / (1 + w^4), so
// dB = -10 lg(1 + w^4), and arg H = -atan2(sqrt(2) w, 1 - w^2).
TEST_CASE("the MSL's ShowTransferFunction draws the Bode plot of its PT2", "[msl]") {
  const std::string name = "e2e_msl_show_transfer_function";
  auto model =
      msl_compiled_model(name, {{kData + "MslComplexBlocks.mo", "ShowTransferFunction", {}, true}, {}, true});
  if (!model) return;
  const auto grid = runtime::OutputGrid::uniform(0, 1, 100);
  const auto p = model->info().default_parameters();
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto lg_w = column(r.trajectory, "lg_w");
  const auto db = column(r.trajectory, "dB");
  const auto phi = column(r.trajectory, "phi");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double w = std::pow(10.0, lg_w[k]);
    INFO("t = " << grid.times[k] << ", w = " << w);
    CHECK(lg_w[k] == Approx(-2 + 4 * grid.times[k]).margin(1e-9));
    CHECK(db[k] == Approx(-10 * std::log10(1 + std::pow(w, 4))).margin(1e-9));
    CHECK(phi[k] == Approx(-std::atan2(std::sqrt(2.0) * w, 1 - w * w)).margin(1e-9));
  }
}
