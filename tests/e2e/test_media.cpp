// Medium packages in the shape of Modelica.Media's: classes a package
// inherits see the classes and constants the package redeclares and
// modifies (MLS 5.6.1, 7.1), and package constants of record type hold the
// gases' data. Our own models against closed forms (MediumVolume: a medium
// package in Media's shape; ReplacedMedia: media put in place by modifiers;
// FixedStartState: the state rule SimpleLiquidWater needs), and three of the
// MSL's Media examples against theirs: SimpleLiquidWater's heating,
// IdealGasH2O's NASA polynomials, MixtureGases' balances.
#include <cmath>
#include <optional>
#include <string>
#include <vector>

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
  const auto r = run_data_model("e2e_medium_volume", "MediumVolume.mo", "MediumVolume", 60, 60);
  const auto t = r->times();
  const auto T = (*r)("medium.T");
  const auto h = (*r)("medium.h");
  const auto mixed = (*r)("mixed.T");
  const auto h_mixed = (*r)("h_mixed");
  const auto der_T = (*r)("der_T");
  const auto n = (*r)("n");
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

TEST_CASE("functions and constants reached through a replaceable package are those of its replacement",
          "[media]") {
  const auto r = run_data_model("e2e_replaced_media", "MediumVolume.mo", "ReplacedMedia", 60, 30);
  const auto t = r->times();
  struct Case {
    const char* name;
    double m, cp, cv;
  };
  for (const Case c : {Case{"oil", 850 * 0.01, 2000, 1800}, Case{"water", 1000 * 0.01, 4184, 4150}}) {
    INFO(c.name);
    const std::string v = c.name;
    const auto T = (*r)(v + ".medium.T");
    const auto h = (*r)(v + ".h_pT");
    const auto n = (*r)(v + ".n");
    for (std::size_t k = 0; k < t.size(); ++k) {
      INFO("t = " << t[k]);
      const double Tk = 300 + 500 * t[k] / (c.m * c.cv);  // m du/dt = Q, u = cv (T - T0)
      CHECK(T[k] == Approx(Tk).epsilon(1e-8));
      CHECK(h[k] == Approx(c.cp * (Tk - 273.15)).epsilon(1e-8));  // Medium.specificEnthalpy_pTX
      CHECK(n[k] == 1);                                            // Medium.nX
    }
  }
}

TEST_CASE("a variable with a fixed start is the state rather than one the model only differentiates",
          "[media][states]") {
  const auto r = run_data_model("e2e_fixed_start_state", "FixedStartState.mo", "FixedStartState", 60, 60);
  const auto t = r->times();
  const auto T = (*r)("T");
  const auto y = (*r)("y");
  for (std::size_t k = 0; k < t.size(); ++k) {
    INFO("t = " << t[k]);
    // U = T (10 + T/1000) = 3090 + t from T(0) = 300.
    const double U = 3090 + t[k];
    const double Tk = (-10 + std::sqrt(100 + 0.004 * U)) / 0.002;
    CHECK(T[k] == Approx(Tk).epsilon(1e-9));
    const double s = t[k] - 20, w = t[k] < 20 ? 0 : t[k] > 40 ? 1 : s * s * (60 - 2 * s) / 8000;
    CHECK(y[k] == Approx(w * Tk + (1 - w) * 280).epsilon(1e-9));
  }
}

TEST_CASE("the MSL's SimpleLiquidWater heats its volume at the rate its medium's constants give", "[msl][media]") {
  const auto r = run_data_model("e2e_msl_simple_liquid_water", "MslMedia.mo", "SimpleLiquidWater", 100, 100, true);
  if (!r) return;
  const auto t = r->times();
  const auto T = (*r)("medium.T");
  const auto state_T = (*r)("state.T");
  const auto der_T = (*r)("der_T");
  const auto der_p = (*r)("der_p");
  const auto eta = (*r)("eta");
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

TEST_CASE("the MSL's IdealGasH2O gives steam's heat capacity by the NASA polynomials of its data record",
          "[msl][media]") {
  const auto r = run_data_model("e2e_msl_ideal_gas_h2o", "MslMedia.mo", "IdealGasH2O", 1, 20, true);
  if (!r) return;
  const auto T = (*r)("state.T");
  const auto cp = (*r)("cp");
  const auto cv = (*r)("cv");
  const auto k = (*r)("k");
  const auto a = (*r)("a");
  // SingleGasesData.H2O: R and the coefficients below and above Tlimit = 1000 K;
  // cp/R = a1/T^2 + a2/T + a3 + a4 T + a5 T^2 + a6 T^3 + a7 T^4.
  const double R = 461.5233290850878;
  const double low[] = {-39479.6083, 575.573102, 0.931782653, 0.00722271286, -7.34255737e-006,
                        4.95504349e-009, -1.336933246e-012};
  const double high[] = {1034972.096, -2412.698562, 4.64611078, 0.002291998307, -6.836830479999999e-007,
                         9.426468930000001e-011, -4.82238053e-015};
  const auto t = r->times();
  for (std::size_t i = 0; i < t.size(); ++i) {
    INFO("t = " << t[i]);
    CHECK(T[i] == Approx(200 + 1000 * t[i]).epsilon(1e-12));
    const double* c = T[i] < 1000 ? low : high;
    double poly = 0;
    for (int j = 6; j >= 0; --j) poly = poly * T[i] + c[j];
    const double cp_nasa = R * poly / (T[i] * T[i]);
    CHECK(cp[i] == Approx(cp_nasa).epsilon(1e-12));
    CHECK(cv[i] == Approx(cp_nasa - R).epsilon(1e-12));
    CHECK(k[i] == Approx(cp_nasa / (cp_nasa - R)).epsilon(1e-12));
    CHECK(a[i] == Approx(std::sqrt(R * T[i] * cp_nasa / (cp_nasa - R))).epsilon(1e-12));
  }
}

TEST_CASE("the MSL's MixtureGases keeps its volumes' mass and energy balances and the ideal gas law",
          "[msl][media]") {
  const auto r = run_data_model("e2e_msl_mixture_gases", "MslMedia.mo", "MixtureGases", 1, 20, true);
  if (!r) return;
  const auto t = r->times();
  for (const std::string v : {"1", "2"}) {
    INFO("volume " << v);
    const auto m = (*r)("m" + v);
    const auto U = (*r)("U" + v);
    const auto pr = (*r)("medium" + v + ".p");
    const auto T = (*r)("medium" + v + ".T");
    const auto d = (*r)("medium" + v + ".d");
    const auto Rg = (*r)("medium" + v + ".R");
    const auto u = (*r)("medium" + v + ".u");
    const auto h = (*r)("medium" + v + ".h");
    // Both start at 1 bar and 300 K (fixed), in 1 m3.
    CHECK(pr[0] == Approx(1e5).epsilon(1e-12));
    CHECK(T[0] == Approx(300).epsilon(1e-12));
    for (std::size_t i = 0; i < t.size(); ++i) {
      INFO("t = " << t[i]);
      // 0.01 kg/s and 5 kW in: m and U grow linearly.
      CHECK(m[i] == Approx(m[0] + 0.01 * t[i]).epsilon(1e-7));
      CHECK(U[i] == Approx(U[0] + 5000 * t[i]).epsilon(1e-7));
      CHECK(pr[i] == Approx(d[i] * Rg[i] * T[i]).epsilon(1e-12));  // p = d R T
      CHECK(u[i] == Approx(h[i] - Rg[i] * T[i]).epsilon(1e-12));   // u = h - R T
      CHECK(m[i] == Approx(d[i]).epsilon(1e-12));                  // V = 1 m3
    }
  }
}
