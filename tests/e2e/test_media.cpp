// Medium packages in the shape of Modelica.Media's: classes a package
// inherits see the classes and constants the package redeclares and
// modifies (MLS 5.6.1, 7.1). Our own MediumVolume.mo against its closed
// form, and the MSL's SimpleLiquidWater example against its own.
#include <cmath>
#include <string>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

/// The smoothed value of Media.Common.smoothStep: y1 above x_small, y2 below
/// -x_small, a cubic between.
double smooth_step(double x, double y1, double y2, double x_small) {
  if (x > x_small) return y1;
  if (x < -x_small) return y2;
  const double s = x / x_small;
  return s * (s * s - 3) * (y2 - y1) / 4 + (y1 + y2) / 2;
}

}  // namespace

TEST_CASE("a medium package's inherited functions and models use its redeclared classes and constants",
          "[media]") {
  auto model = compiled_model("e2e_medium_volume", {{kData + "MediumVolume.mo", "MediumVolume"}, {}, true});
  const auto p = model->info().default_parameters();
  const auto grid = runtime::OutputGrid::uniform(0, 60, 60);
  auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto& tab = r.trajectory;
  const auto t = tab.times();
  const auto T = variable("e2e_medium_volume", tab, p, "medium.T");
  const auto h = variable("e2e_medium_volume", tab, p, "medium.h");
  const auto mixed = variable("e2e_medium_volume", tab, p, "mixed.T");
  const auto h_mixed = variable("e2e_medium_volume", tab, p, "h_mixed");
  const auto der_T = variable("e2e_medium_volume", tab, p, "der_T");
  const auto n = variable("e2e_medium_volume", tab, p, "n");
  // Oil: 850 kg/m3 in 0.01 m3, cv 1800 J/(kg K), 500 W: the volume's
  // temperature rises at Q / (m cv) from its initial 300 K.
  const double rate = 500.0 / (850 * 0.01 * 1800);
  for (std::size_t k = 0; k < t.size(); ++k) {
    INFO("t = " << t[k]);
    const double Tk = 300 + rate * t[k];
    CHECK(T[k] == Approx(Tk).epsilon(1e-8));
    // specificEnthalpy_pTX of the base package, through Oil's setState_pTX
    // and specificEnthalpy: cp (T - T0) with Oil's cp and T0.
    CHECK(h[k] == Approx(2000 * (Tk - 273.15)).epsilon(1e-8));
    const double mk = smooth_step(t[k] - 30, Tk, 280, 10);
    CHECK(mixed[k] == Approx(mk).epsilon(1e-8));
    CHECK(h_mixed[k] == Approx(2000 * (mk - 273.15)).epsilon(1e-8));
    if (t[k] < 19.5) CHECK(std::fabs(der_T[k]) < 1e-12);
    if (t[k] > 40.5) CHECK(der_T[k] == Approx(rate).epsilon(1e-8));
    CHECK(n[k] == 1);  // nX = size(substanceNames, 1), substanceNames = {mediumName}
  }
}

TEST_CASE("the MSL's SimpleLiquidWater heats its volume at the rate its medium's constants give", "[msl][media]") {
  auto model = msl_compiled_model("e2e_msl_simple_liquid_water",
                                  {{kData + "MslMedia.mo", "SimpleLiquidWater"}, {}, true});
  if (!model) return;
  const auto p = model->info().default_parameters();
  const auto grid = runtime::OutputGrid::uniform(0, 100, 100);
  auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto& tab = r.trajectory;
  const auto t = tab.times();
  const auto T = variable("e2e_msl_simple_liquid_water", tab, p, "medium.T");
  const auto state_T = variable("e2e_msl_simple_liquid_water", tab, p, "state.T");
  const auto der_T = variable("e2e_msl_simple_liquid_water", tab, p, "der_T");
  const auto der_p = variable("e2e_msl_simple_liquid_water", tab, p, "der_p");
  const auto eta = variable("e2e_msl_simple_liquid_water", tab, p, "eta");
  // ConstantPropertyLiquidWater: d = 995.586 kg/m3, cv = 4184 J/(kg K);
  // 1 MW into 1 m3 from T = 300 K; medium2 at 330 K and p = 1e4 t Pa.
  const double rate = 1e6 / (995.586 * 4184);
  for (std::size_t k = 0; k < t.size(); ++k) {
    INFO("t = " << t[k]);
    const double Tk = 300 + rate * t[k];
    CHECK(T[k] == Approx(Tk).epsilon(1e-8));
    CHECK(state_T[k] == Approx(smooth_step(t[k] - 30, Tk, 330, 10)).epsilon(1e-8));
    if (t[k] < 19.5) {
      CHECK(std::fabs(der_T[k]) < 1e-12);
      CHECK(der_p[k] == Approx(1e4).epsilon(1e-10));
    }
    if (t[k] > 40.5) {
      CHECK(der_T[k] == Approx(rate).epsilon(1e-8));
      CHECK(std::fabs(der_p[k]) < 1e-12);
    }
    CHECK(eta[k] == Approx(1e-3).epsilon(1e-12));  // the medium's eta_const
  }
}
