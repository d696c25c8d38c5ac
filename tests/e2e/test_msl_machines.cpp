// The MSL's Electrical.Machines (tests/e2e/data/MslMachines.mo): the direct-on-line
// start of an induction machine settles at the nominal speed its example was
// built for. The machine's model exercises multi-phase plugs (whose phase
// count m is a connected parameter), arrays of components with switched-off
// conditional heat ports, and Boolean constants passed on in modifiers. Also
// two of the PowerConverters examples (thyristor and diode bridges).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <string>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

/// 1440.45 rpm: the induction machine examples' nominal speed, in rad/s.
const double kNominalSpeed = 1440.45 * 2 * M_PI / 60;

/// The class `cls` of MslMachines.mo, compiled once as `name` against the
/// MSL of ../shared (found on MODELICAPATH, as a user runs it), simulated
/// from 0 to `stop` on `intervals` intervals; REQUIREs success. nullopt
/// (skipped) without ../shared.
std::optional<runtime::SimulationResult> run_example(const std::string& name, const std::string& cls, double stop,
                                                     std::size_t intervals) {
  auto model = msl_compiled_model(name, {{kData + "MslMachines.mo", cls, {}, true}, {}});
  if (!model) return std::nullopt;
  const auto grid = runtime::OutputGrid::uniform(0, stop, intervals);
  auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  return r;
}

}  // namespace

TEST_CASE("the MSL's AIMC_DOL starts and settles at the nominal speed", "[msl]") {
  const auto r = run_example("e2e_msl_aimc_dol", "AimcDol", 1.5, 150);
  if (!r) return;
  const auto w = column(r->trajectory, "aimc.wMechanical");
  // At rest until the switch closes at 0.1 s.
  CHECK(std::fabs(w[5]) < 1e-9);
  // Settled at the load's nominal point, 1440.45 rpm (where the machine's
  // torque meets the quadratic load's 161.4 N.m).
  CHECK(w.back() == Approx(kNominalSpeed).epsilon(1e-4));
  CHECK(w[140] == Approx(w.back()).epsilon(1e-6));
  // Accelerating on the way: below half the nominal speed at 0.2 s.
  CHECK(w[20] > 0.0);
  CHECK(w[20] < 0.5 * kNominalSpeed);
}

TEST_CASE("the MSL's AIMC_Inverter ramps up and carries the nominal load at the nominal speed", "[msl]") {
  const auto r = run_example("e2e_msl_aimc_inverter", "AimcInverter", 1.5, 150);
  if (!r) return;
  const auto w = column(r->trajectory, "aimc.wMechanical");
  const auto tau = column(r->trajectory, "tau");
  const auto i0 = column(r->trajectory, "i0");
  // No-load, just below synchronous speed (2 pole pairs, 50 Hz) before the step.
  CHECK(w[115] == Approx(50 * M_PI).epsilon(2e-3));
  CHECK(w[115] < 50 * M_PI);
  // 0.3 s after the step: the nominal point, 1440.45 rpm and 161.4 N.m.
  CHECK(w.back() == Approx(kNominalSpeed).epsilon(1e-4));
  CHECK(tau.back() == Approx(161.4).epsilon(1e-3));
  // The open star point carries no zero-sequence current.
  for (double x : i0) CHECK(std::fabs(x) < 1e-9);
}

TEST_CASE("the MSL's TransformerTestbench balances its power over a period", "[msl]") {
  const auto r = run_example("e2e_msl_transformer", "TransformerTestbench", 0.1, 1000);
  if (!r) return;
  const auto p1 = column(r->trajectory, "power1"), p2 = column(r->trajectory, "power2");
  const auto loss = column(r->trajectory, "loss");
  // Over the last two periods (50 Hz): what enters the primary leaves the
  // secondary but for the copper losses, about the 300 W of the short-circuit
  // test at nominal power (the load draws a little less).
  double in = 0, out = 0, lost = 0;
  for (std::size_t k = 600; k < 1000; ++k) in += p1[k], out += p2[k], lost += loss[k];
  CHECK(in > 25e3 * 400);
  CHECK(in + out == Approx(lost).epsilon(1e-2));
  CHECK(lost / 400 > 250);
  CHECK(lost / 400 < 300);
}

TEST_CASE("the MSL's DCPM_withLosses starts from rest and both machines reach their nominal points", "[msl]") {
  // At rest, the losses' derivatives along their exponents were NaN
  // (log(0)), and the run stopped at t = 0.
  const auto r = run_example("e2e_msl_dcpm_losses", "DcpmWithLosses", 2, 200);
  if (!r) return;
  const auto w1 = column(r->trajectory, "dcpm1.wMechanical"), w2 = column(r->trajectory, "dcpm2.wMechanical");
  const auto ia1 = column(r->trajectory, "ia1"), ia2 = column(r->trajectory, "ia2");
  CHECK(std::fabs(w1[10]) < 1e-9);  // before the ramp at 0.2 s
  // The loads' nominal points (wLoad1, wLoad2 of the example): 1425 rpm
  // without losses, 1417.5 rpm with them, both at the nominal armature
  // current of 100 A.
  CHECK(w1.back() == Approx(1425 * 2 * M_PI / 60).epsilon(1e-4));
  CHECK(w2.back() < w1.back());
  CHECK(w2.back() == Approx(1417.5 * 2 * M_PI / 60).epsilon(1e-4));
  CHECK(ia1.back() == Approx(100).epsilon(1e-3));
  CHECK(ia2.back() == Approx(100).epsilon(1e-3));
}

TEST_CASE("the MSL's AIMC_Initialize starts in steady state and then carries the nominal load", "[msl]") {
  const auto r = run_example("e2e_msl_aimc_initialize", "AimcInitialize", 1.5, 150);
  if (!r) return;
  const auto w = column(r->trajectory, "aimc.wMechanical");
  const auto tau = column(r->trajectory, "tau");
  // Steady at synchronous speed (2 pole pairs, 50 Hz) with no torque: the
  // initial equations put every current where it stays.
  for (std::size_t k = 0; k < 50; ++k) {
    CHECK(w[k] == Approx(50 * M_PI).epsilon(1e-9));
    CHECK(std::fabs(tau[k]) < 1e-6);
  }
  CHECK(w.back() == Approx(kNominalSpeed).epsilon(1e-4));
  CHECK(tau.back() == Approx(161.4).epsilon(1e-3));
}

TEST_CASE("the MSL's DCPM_Temperature warms up to its reference temperature and the nominal point", "[msl]") {
  const auto r = run_example("e2e_msl_dcpm_temperature", "DcpmTemperature", 3, 300);
  if (!r) return;
  const auto w = column(r->trajectory, "dcpm.wMechanical");
  // Warm, the armature has the unmodified machine's resistance: 1425 rpm at
  // the nominal load (within the exponential's remaining 0.3 K).
  CHECK(w.back() == Approx(1425 * 2 * M_PI / 60).epsilon(2e-4));
  CHECK(w.front() > w.back());  // from no-load speed
}

TEST_CASE("the MSL's AIMC_Conveyor runs forwards and backwards at the nominal point", "[msl]") {
  const auto r = run_example("e2e_msl_aimc_conveyor", "AimcConveyor", 20, 200);
  if (!r) return;
  const auto w = column(r->trajectory, "aimc.wMechanical");
  CHECK(w[30] == Approx(kNominalSpeed).epsilon(1e-4));    // t = 3 s, forwards
  CHECK(w[130] == Approx(-kNominalSpeed).epsilon(1e-4));  // t = 13 s, backwards
  CHECK(std::fabs(w[80]) < 1e-6);                         // t = 8 s, at rest
}

TEST_CASE("the MSL's Rectifier12pulse commutates every 30 degrees at its DC voltage", "[msl]") {
  const auto r = run_example("e2e_msl_rectifier12", "Rectifier12pulse", 0.1, 1000);
  if (!r) return;
  // Each of the 12 diodes turns on and off once per 20 ms period: 24 events
  // in each of the last two periods (relations of a Newton block, each an event).
  const auto events_in = [&](double from, double to) {
    return std::count_if(r->event_times.begin(), r->event_times.end(),
                         [&](double t) { return t >= from && t < to; });
  };
  CHECK(events_in(0.06, 0.08) == 24);
  CHECK(events_in(0.08, 0.1) == 24);
  // The DC voltage over the last period: a 6-pulse bridge's 3 sqrt(2)/pi of
  // the 100 V line voltage, less the commutation drop (3/pi) X Id and the
  // resistive drop 2 R Id per bridge, X and R from the transformers' 5 %
  // impedance and 300 W copper losses at 30 kVA (both bridges carry Id).
  const auto v = column(r->trajectory, "vLoad");
  const double mean = std::accumulate(v.begin() + 800, v.end(), 0.0) / double(v.size() - 800);
  const double Z = 0.05 * 100 * 100 / 30e3, R = 300 / 30e3 / 3, X = std::sqrt(Z * Z - R * R);
  const double Id = mean / 0.2 / 2;
  const double expected = 3 * std::sqrt(2) / M_PI * 100 - 3 / M_PI * X * Id - 2 * R * Id;
  CHECK(mean == Approx(expected).epsilon(1e-2));
  // Twelve pulses per period: a ripple of about 2 % (a 6-pulse bridge: 20 %).
  const auto [lo, hi] = std::minmax_element(v.begin() + 800, v.end());
  CHECK(*hi - *lo < 0.03 * mean);
}

TEST_CASE("the MSL's SMEE_LoadDump holds its voltage with and without the load", "[msl]") {
  const auto r = run_example("e2e_msl_smee_load_dump", "SmeeLoadDump", 10, 10000);
  if (!r) return;
  const auto V = column(r->trajectory, "V"), I = column(r->trajectory, "I");
  const auto tau = column(r->trajectory, "tau"), ie = column(r->trajectory, "ie");
  const double w = 50 * M_PI;  // 1500 rpm
  for (std::size_t k : {1900, 5900, 9900}) {  // no load: the open-circuit point
    INFO("t = " << k / 1000.0);
    CHECK(V[k] == Approx(100).epsilon(1e-3));
    CHECK(ie[k] == Approx(10).epsilon(2e-3));  // smeeData.IeOpenCircuit
    CHECK(std::fabs(tau[k]) < 0.01);
  }
  for (std::size_t k : {3900, 7900}) {  // loaded: 100 V across 1 Ohm per phase
    INFO("t = " << k / 1000.0);
    CHECK(V[k] == Approx(100).epsilon(1e-3));
    CHECK(I[k] == Approx(100).epsilon(1e-3));
    // The generator delivers the load's 3 I^2 R = 24 kW and its own losses.
    const double load = 3 * I[k] * I[k] * 0.8;
    CHECK(-tau[k] * w > load);
    CHECK(-tau[k] * w < 1.05 * load);
  }
  // Switched at 2, 4, 6 and 8 s (and the arcs quench after 4 and 8 s).
  CHECK(std::count_if(r->event_times.begin(), r->event_times.end(),
                      [](double t) { return std::fabs(t - 2) < 1e-9 || std::fabs(t - 6) < 1e-9; }) == 2);
}

TEST_CASE("the MSL's PowerConverters bridges give their rectified mean and RMS voltages", "[msl]") {
  const double Vrms = 110, alpha = M_PI / 6, R = 20;
  {  // single-phase, fully controlled, resistive load: conducting from alpha to pi
    const auto r = run_example("e2e_msl_thyristor_bridge", "ThyristorBridge2PulseR", 0.1, 500);
    if (!r) return;
    const double mean = std::sqrt(2) * Vrms / M_PI * (1 + std::cos(alpha));
    const double rms = Vrms * std::sqrt(1 - alpha / M_PI + std::sin(2 * alpha) / (2 * M_PI));
    for (std::size_t k : {200, 450, 499}) {  // after the first period, between ticks too
      INFO("t = " << k * 0.0002);
      CHECK(column(r->trajectory, "vMean")[k] == Approx(mean).epsilon(1e-5));
      CHECK(column(r->trajectory, "vRms")[k] == Approx(rms).epsilon(1e-5));
      CHECK(column(r->trajectory, "iMean")[k] == Approx(mean / R).epsilon(1e-5));
    }
  }
  {  // three-phase diode bridge: 3 sqrt(6)/pi of the phase voltage
    const auto r = run_example("e2e_msl_diode_bridge", "DiodeBridge2mPulse", 0.1, 500);
    if (!r) return;
    for (std::size_t k : {250, 499})
      CHECK(column(r->trajectory, "vMean")[k] == Approx(3 * std::sqrt(6) / M_PI * Vrms).epsilon(1e-5));
  }
}
