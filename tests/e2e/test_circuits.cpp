// Scilab's Electrical circuits, flat as modelicat wrote them, against their
// analytic solutions. The parameters are read from the hierarchical source
// .mo files (modelicat inlines most of them into the flat file).
#include <cmath>
#include <complex>
#include <fstream>
#include <regex>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The number in the first match of `pattern` (one capture group) in `file`.
double number_in(const std::string& file, const std::string& pattern) {
  const std::string text = slurp(file);
  std::smatch m;
  INFO(pattern << " in " << file);
  REQUIRE(std::regex_search(text, m, std::regex(pattern)));
  return std::stod(m[1].str());
}

const std::string kNumber = R"(([-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?))";

}  // namespace

TEST_CASE("Scilab RCCharge (modelicat flat) charges as V(1 - exp(-t/RC))") {
  const std::string source = kScilab + "RCCharge.mo";
  const double V = number_in(source, R"(parameter Real V_11\(fixed=false\) = )" + kNumber);
  const double R = number_in(source, R"(parameter Real R_21\(fixed=false\) = )" + kNumber);
  const double C = number_in(source, R"(parameter Real C_31\(fixed=false\) = )" + kNumber);
  auto model = compiled_model("e2e_rc_charge", {{kScilab + "RCCharge.flat.mo", "", {}, true}, {}});
  const double tau = R * C;
  const auto grid = runtime::OutputGrid::uniform(0, 5 * tau, 200);
  const auto p = model->info().default_parameters();
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  // Lowering may keep another variable as the state (C1.v = V - R*i): C1.v
  // is then recovered from the value lowering recorded for it.
  const auto v = variable("e2e_rc_charge", r.trajectory, p, "C1.v");
  double worst = 0;
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double t = grid.times[k], exact = V * (1 - std::exp(-t / tau));
    INFO("t = " << t);
    CHECK(std::fabs(v[k] - exact) <= 1e-6 * V);
    worst = std::max(worst, std::fabs(v[k] - exact));
  }
  WARN("RCCharge: max |C1.v - exact| = " << worst << " V (V = " << V << ")");
  CHECK(v.back() > 0.99 * V);
}

TEST_CASE("Scilab RLCSeries (modelicat flat) step response equals the analytic one") {
  const std::string source = kScilab + "RLCSeries.mo";
  const double R = number_in(source, R"(parameter Real R0 = )" + kNumber);
  const double L = number_in(source, R"(parameter Real L0 = )" + kNumber);
  const double C = number_in(source, R"(parameter Real C0 = )" + kNumber);
  const double V = number_in(source, R"(ConstantVoltage\s+V1\(V=)" + kNumber);
  // Step response of a series RLC from rest: alpha = R/2L, w0 = 1/sqrt(LC).
  const double alpha = R / (2 * L), w0 = 1 / std::sqrt(L * C);
  auto exact = [&](double t) -> std::pair<double, double> {  // (C1.v, L1.i)
    if (alpha < w0) {  // under-damped
      const double wd = std::sqrt(w0 * w0 - alpha * alpha), e = std::exp(-alpha * t);
      return {V * (1 - e * (std::cos(wd * t) + alpha / wd * std::sin(wd * t))), V / (L * wd) * e * std::sin(wd * t)};
    }
    if (alpha > w0) {  // over-damped: roots s1, s2 < 0
      const double q = std::sqrt(alpha * alpha - w0 * w0), s1 = -alpha + q, s2 = -alpha - q;
      return {V * (1 + (s2 * std::exp(s1 * t) - s1 * std::exp(s2 * t)) / (s1 - s2)),
              V / (L * (s1 - s2)) * (std::exp(s1 * t) - std::exp(s2 * t))};
    }
    return {V * (1 - std::exp(-alpha * t) * (1 + alpha * t)), V / L * t * std::exp(-alpha * t)};  // critical
  };
  auto model = compiled_model("e2e_rlc_series", {{kScilab + "RLCSeries.flat.mo", "", {}, true}, {}});
  const double t_end = 10 / alpha;
  const auto grid = runtime::OutputGrid::uniform(0, t_end, 400);
  const auto p = model->info().default_parameters();
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto v = variable("e2e_rlc_series", r.trajectory, p, "C1.v");
  const auto i = variable("e2e_rlc_series", r.trajectory, p, "L1.i");
  double worst_v = 0, worst_i = 0;
  const double i_scale = V / (L * w0);
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const auto [ve, ie] = exact(grid.times[k]);
    INFO("t = " << grid.times[k]);
    CHECK(std::fabs(v[k] - ve) <= 1e-6 * V);
    CHECK(std::fabs(i[k] - ie) <= 1e-6 * i_scale);
    worst_v = std::max(worst_v, std::fabs(v[k] - ve));
    worst_i = std::max(worst_i, std::fabs(i[k] - ie));
  }
  WARN("RLCSeries (" << (alpha < w0 ? "under" : "over") << "-damped, zeta = " << alpha / w0
                     << "): max |dv| = " << worst_v << " V, max |di| = " << worst_i << " A");
  // Under-damped: the capacitor voltage overshoots V.
  if (alpha < w0) CHECK(*std::max_element(v.begin(), v.end()) > 1.1 * V);
}

TEST_CASE("a nested if-equation under varying conditions switches closed, arc, quenched (IdealSwitchWithArc)") {
  // tests/e2e/data/NestedIfSwitch.mo: each branch solves for another
  // variable. Closed: tau1 = (R + Ron) C; arc: vc -> V - Varc with tau = RC,
  // until i = (V - Varc - vc)/R falls to Varc*Goff; quenched: i = Goff v,
  // tau3 = C (1 + R Goff)/Goff.
  const double V = 10, R = 10, C = 0.01, Ron = 1e-3, Goff = 1e-2, Varc = 2, tOff = 0.05;
  const double vc_off = V * (1 - std::exp(-tOff / ((R + Ron) * C)));
  const double a = V - Varc;
  const double t_q = tOff + R * C * std::log((a - vc_off) / (R * Varc * Goff));
  const double vc_q = a - R * Varc * Goff;
  const double tau3 = C * (1 + R * Goff) / Goff;
  const auto exact = [&](double t) {
    if (t < tOff) return V * (1 - std::exp(-t / ((R + Ron) * C)));
    if (t < t_q) return a + (vc_off - a) * std::exp(-(t - tOff) / (R * C));
    return V - (V - vc_q) * std::exp(-(t - t_q) / tau3);
  };
  auto model = compiled_model("e2e_nested_if_switch", {{kData + "NestedIfSwitch.mo", "", {}, true}, {}});
  const auto r = simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 1, 50), "vc", exact, 1e-6);
  // `off = time >= tOff` is a discrete Boolean: its change at tOff is an event
  REQUIRE(r.event_times.size() == 2);
  // After the quench abs(i) - abs(v)*Goff stays at 0 ± rounding: its roots
  // change nothing and must not restart the integrator (hundreds of restarts
  // cost 5e-6 here).
  CHECK(r.statistics.restarts < 10);
  CHECK(r.event_times[0] == Approx(tOff).margin(1e-12));
  CHECK(r.event_times[1] == Approx(t_q).margin(1e-7));
}

TEST_CASE("ideal diodes in an algebraic loop switch at events, held between them (HalfWaveDiode)", "[events]") {
  // tests/e2e/data/HalfWaveDiode.mo: the diode conducts while the source is
  // above c = Vknee (1 + R Goff); on, i = (u - c)/(Ron + R) + Goff Vknee and
  // vd = Ron (u - c)/(Ron + R) + Vknee, off, i = Goff u/(1 + R Goff) = Goff vd;
  // both equal at the switch.
  const double V = 10, f = 50, R = 10, Ron = 1e-2, Goff = 1e-5, Vknee = 0.7, stop = 0.05;
  const double w = 2 * M_PI * f, c = Vknee * (1 + R * Goff), a = std::asin(c / V);
  std::vector<double> switches;  // on at (a + 2 pi k)/w, off at (pi - a + 2 pi k)/w
  for (int k = 0; k < 3; ++k)
    for (double phase : {a, M_PI - a})
      if (const double t = (phase + 2 * M_PI * k) / w; t < stop) switches.push_back(t);
  const auto on = [&](double t) { return V * std::sin(w * t) >= c; };
  const auto diode_voltage = [&](double t) {
    const double u = V * std::sin(w * t);
    return on(t) ? Ron * (u - c) / (Ron + R) + Vknee : u / (1 + R * Goff);
  };
  // q: the antiderivative of each phase's current, summed over the phases.
  const auto primitive = [&](double t, bool conducting) {
    const double cosine = -V * std::cos(w * t) / w;
    return conducting ? (cosine - c * t) / (Ron + R) + Goff * Vknee * t : Goff * cosine / (1 + R * Goff);
  };
  const auto charge = [&](double t) {
    double q = 0, from = 0;
    for (double s : switches) {
      if (s >= t) break;
      q += primitive(s, on(0.5 * (from + s))) - primitive(from, on(0.5 * (from + s)));
      from = s;
    }
    return q + primitive(t, on(0.5 * (from + t))) - primitive(from, on(0.5 * (from + t)));
  };
  auto model = compiled_model("e2e_half_wave_diode", {{kData + "HalfWaveDiode.mo", "", {}, true}, {}});
  bool off_is_discrete = false;
  for (const auto& d : model->info().discrete) off_is_discrete = off_is_discrete || d.name == "off";
  CHECK(off_is_discrete);
  const auto grid = runtime::OutputGrid::uniform(0, stop, 500);
  const auto r = simulate_against_exact(*model, grid, "q", charge, 1e-9);
  // Each switch is an event, found by its indicator s (no event otherwise).
  REQUIRE(r.event_times.size() == switches.size());
  for (std::size_t k = 0; k < switches.size(); ++k) CHECK(r.event_times[k] == Approx(switches[k]).margin(1e-9));
  const auto vd = column(r.trajectory, "vd");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    INFO("t = " << grid.times[k]);
    CHECK(vd[k] == Approx(diode_voltage(grid.times[k])).margin(1e-9));
  }
}

TEST_CASE("a parameter with annotation(Evaluate = true) is structural: C = 0 leaves no capacitor state") {
  // tests/e2e/data/EvaluatedCapacitance.mo
  auto model = compiled_model("e2e_evaluated_capacitance",
                              {{kData + "EvaluatedCapacitance.mo", "", {}, true}, {}});
  CHECK(model->info().states.empty());
  for (const auto& q : model->info().parameters) CHECK(q.name != "CapVal");
  simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 2, 20), "v",
                         [](double t) { return 2 * std::sin(t); }, 1e-12);
}

TEST_CASE("Evaluate = true on a record parameter covers its fields: Cj = 0 leaves the junction algebraic") {
  // tests/e2e/data/EvaluatedCard.mo (the MSL Spice3 devices' model cards)
  auto model = compiled_model("e2e_evaluated_card",
                              {{kData + "EvaluatedCard.mo", "EvaluatedCard.Circuit", {}, true}, {}});
  REQUIRE(model->info().states.size() == 1);
  CHECK(model->info().states[0].name == "v");
  for (const auto& q : model->info().parameters) {
    CHECK(q.name.rfind("card.", 0) != 0);
    CHECK(q.name.rfind("junction.", 0) != 0);
  }
  simulate_against_exact(*model, runtime::OutputGrid::uniform(0, 2, 20), "v",
                         [](double t) { return std::exp(-t / (0.5 * (1 + 3))); }, 1e-7);
}

TEST_CASE("a loop closed through expandable connectors follows its closed form (BusLoop)", "[expandable]") {
  // The plant's speed reaches the controller through a sub-bus and two
  // connected buses; the command goes back as an element no bus declares.
  auto model = compiled_model("e2e_bus_loop", {{kData + "BusLoop.mo", "BusLoop.Loop", {}, true}, {}});
  const auto p = model->info().default_parameters();
  const auto grid = runtime::OutputGrid::uniform(0, 3, 30);
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const double T = 2, k = 3;
  const auto w = variable("e2e_bus_loop", r.trajectory, p, "plant.w");
  const auto on_bus = variable("e2e_bus_loop", r.trajectory, p, "bus.sub.speed");
  const auto command = variable("e2e_bus_loop", r.trajectory, p, "bus.command");
  for (std::size_t i = 0; i < grid.times.size(); ++i) {
    const double t = grid.times[i], exact = k / (k + 1) * (1 - std::exp(-(k + 1) * t / T));
    INFO("t = " << t);
    CHECK(w[i] == Approx(exact).margin(1e-7));
    CHECK(on_bus[i] == Approx(exact).margin(1e-7));
    CHECK(command[i] == Approx(k * (1 - exact)).margin(1e-6));
  }
}

TEST_CASE("an open star point with a zero-sequence inductor keeps i0 = 0 and the phasor exact (StarZeroSequence)",
          "[states]") {
  // Both the star point and the zero-sequence transformation fix Σ i_k: the
  // dummy derivatives must include i0's, or the phase currents' block is
  // singular at t = 0 (the MSL's inverter-fed machines stopped there).
  auto model = compiled_model("e2e_star_zero_sequence", {{kData + "StarZeroSequence.mo", "StarZeroSequence", {}}, {}});
  const auto grid = runtime::OutputGrid::uniform(0, 0.1, 200);
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto& t = grid.times;
  const auto a = column(r.trajectory, "i_[1]"), b = column(r.trajectory, "i_[2]");
  const auto i0 = column(r.trajectory, "iZero"), i1 = column(r.trajectory, "iPhase1");
  // i(t) = V/(R + jωL)·(e^{jωt} − e^{−Rt/L}).
  const double V = 10, w = 2 * M_PI * 50, R = 1, L = 0.01;
  const std::complex<double> k = V / std::complex<double>(R, w * L);
  for (std::size_t n = 0; n < t.size(); ++n) {
    const std::complex<double> exact = k * (std::exp(std::complex<double>(0, w * t[n])) - std::exp(-R * t[n] / L));
    INFO("t = " << t[n]);
    CHECK(a[n] == Approx(exact.real()).margin(1e-5));
    CHECK(b[n] == Approx(exact.imag()).margin(1e-5));
    CHECK(std::fabs(i0[n]) < 1e-9);
    // Phase 1 carries the phasor's real part (Σ i_k = 0).
    CHECK(i1[n] == Approx(exact.real()).margin(1e-5));
  }
}

TEST_CASE("a Jacobian that overflows where the right-hand side does not is taken by differences (RegularisedFriction)",
          "[robustness]") {
  // d/dv of 2/(1 + exp(-v/1e-5)) at v = -5 is inf/inf: the model's own
  // Jacobian is not finite, and CVODES stopped at t = 0. The simulation now
  // differentiates the right-hand side there and says how often it did.
  auto model = compiled_model("e2e_regularised_friction", {{kData + "RegularisedFriction.mo", "", {}, true}, {}});
  const auto grid = runtime::OutputGrid::uniform(0, 1.5, 150);
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(r.statistics.difference_jacobians > 0);
  const auto v = column(r.trajectory, "v"), s = column(r.trajectory, "s");
  for (std::size_t k = 0; k <= 90; ++k) {  // t ≤ 0.9: v = -5 + 5t, s = -5t + 2.5t²
    const double t = grid.times[k];
    CHECK(v[k] == Approx(-5 + 5 * t).margin(1e-6));
    CHECK(s[k] == Approx(-5 * t + 2.5 * t * t).margin(1e-6));
  }
  CHECK(std::fabs(v.back()) < 1e-4);  // held near rest by the regularised friction
}
