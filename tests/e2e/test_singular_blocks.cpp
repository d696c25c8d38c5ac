// Linear blocks that become singular while a model runs (runtime
// solve_linear): consistent equations get their minimum-norm solution and a
// warning naming the block, contradicting ones stop the run. Checked on a
// shaft clamped by two brakes (exact), on two friction elements stuck at once
// (the event iteration's cycle at a tie, codegen's solve_mixed), and on the
// MSL's LossyGearDemo2 against its reference result (Dymola's), flags too.
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

ModelSpec spec(const std::string& name) {
  return {{kData + "SingularBlocks.mo", "SingularBlocks." + name, {}, true}, {}, true};
}

/// The columns of a reference .csv (header of quoted names, rows of numbers).
std::map<std::string, std::vector<double>> read_reference(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string cell; std::getline(header, cell, ',');)
    names.push_back(cell.size() >= 2 && cell.front() == '"' ? cell.substr(1, cell.size() - 2) : cell);
  std::map<std::string, std::vector<double>> out;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::size_t k = 0;
    for (std::string cell; std::getline(row, cell, ',') && k < names.size(); ++k) out[names[k]].push_back(std::stod(cell));
  }
  return out;
}

}  // namespace

TEST_CASE("a singular block with consistent equations: the least-norm split of two clamps, and a warning") {
  auto model = compiled_model("e2e_two_clamps", spec("TwoClamps"));
  const auto p = model->info().default_parameters();
  const auto grid = runtime::OutputGrid::uniform(0, 2, 40);
  const auto r = runtime::simulate(*model, {}, p, grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  // J w' = tau - (d1 + d2) w until t_hold = 1, then held: w' = 0.
  const double J = 2, tau = 1, d = 0.75;
  const auto w_exact = [&](double t) { return tau / d * (1 - std::exp(-d * std::min(t, 1.0) / J)); };
  const auto w = column(r.trajectory, "w"), tau1 = column(r.trajectory, "tau1"), tau2 = column(r.trajectory, "tau2");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double t = grid.times[k];
    INFO("t = " << t);
    CHECK(w[k] == Approx(w_exact(t)).margin(1e-7));
    if (t >= 1.0) {  // a = 0, tau1 + tau2 = tau: the least norm shares it equally
      CHECK(tau1[k] == Approx(tau / 2).margin(1e-12));
      CHECK(tau2[k] == Approx(tau / 2).margin(1e-12));
    } else {
      CHECK(tau1[k] == Approx(0.5 * w[k]).margin(1e-12));
    }
  }
  REQUIRE(r.warnings.size() == 1);
  CHECK(r.warnings[0].find("linear block 1 for der(w), tau1, tau2 was singular in ") == 0);
  CHECK(r.warnings[0].find("the earliest at t = 1:") != std::string::npos);
  // A second run starts counting again.
  const auto again = runtime::simulate(*model, {}, p, grid, tight());
  REQUIRE(again.warnings.size() == 1);
  CHECK(again.warnings[0] == r.warnings[0]);
  // Released before they clamp: nothing singular, no warning.
  std::vector<double> later = p;
  later[parameter(model->info(), "t_hold")] = 5;
  const auto free = runtime::simulate(*model, {}, later, grid, tight());
  REQUIRE(free.ok());
  CHECK(free.warnings.empty());
}

TEST_CASE("a singular block whose equations contradict each other stops the run there") {
  auto model = compiled_model("e2e_contradicting_clamps", spec("ContradictingClamps"));
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(),
                                   runtime::OutputGrid::uniform(0, 2, 40), tight());
  CHECK_FALSE(r.ok());
  REQUIRE(r.non_finite_rhs);
  CHECK(r.non_finite_rhs->t == Approx(1.0).margin(1e-9));
  CHECK(r.trajectory.times().back() < 1.0);
}

TEST_CASE("two friction elements stuck at once: the cycle of their event iteration ends at the weak one's limit") {
  auto model = compiled_model("e2e_bearing_and_brake", spec("BearingAndBrake"));
  const auto grid = runtime::OutputGrid::uniform(0, 1, 40);
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  // Sliding forward, J w' = drive - 0.5 - 10, until w = 0 at 1/8.5; then at
  // rest with the bearing sliding-ready at its limit and the brake holding.
  const double t_stop = 1.0 / 8.5;
  const auto w = column(r.trajectory, "w"), bearing = column(r.trajectory, "bearing.tau"),
             brake = column(r.trajectory, "brake.tau"), start = column(r.trajectory, "bearing.startForward"),
             locked = column(r.trajectory, "bearing.locked"), held = column(r.trajectory, "brake.locked"),
             mode = column(r.trajectory, "bearing.mode");
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    const double t = grid.times[k];
    INFO("t = " << t);
    if (t < t_stop) {
      CHECK(w[k] == Approx(1 - 8.5 * t).margin(1e-9));
      CHECK(bearing[k] == 0.5);
      CHECK(brake[k] == 10);
    } else {
      CHECK(std::fabs(w[k]) < 1e-12);
      CHECK(bearing[k] == Approx(0.5).margin(1e-12));
      CHECK(brake[k] == Approx(1.5).margin(1e-12));
      CHECK(start[k] == 1);
      CHECK(locked[k] == 0);
      CHECK(mode[k] == 0);
      CHECK(held[k] == 1);
    }
  }
}

TEST_CASE("the MSL's LossyGearDemo2 (gear and bearing stuck together) follows its reference", "[msl]") {
  auto model = msl_compiled_model("e2e_msl_lossy_gear_demo2",
                                  {{kData + "MslFriction.mo", "LossyGearDemo2", {}, true}, {}, true});
  if (!model) return;
  const auto ref = read_reference(shared_third_party_dir() +
                                  "/third_party/msl-reference-results-3.2.3/Modelica/Mechanics/Rotational/Examples/"
                                  "LossyGearDemo2/LossyGearDemo2.csv");
  const auto grid = runtime::OutputGrid::uniform(0, 0.5, 1000);  // the reference's rows, 0.5 ms apart
  runtime::SimulationOptions opt;
  opt.relative_tolerance = 1e-6;  // the reference's
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, opt);
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(!r.warnings.empty());  // both stuck at t = 0
  const auto& t_ref = ref.at("time");
  for (const std::string name : {"Inertia2.phi", "Inertia2.w"}) {
    const auto ours = column(r.trajectory, name);
    const auto& theirs = ref.at(name);
    double range = 0;
    for (double v : theirs) range = std::max(range, std::fabs(v));
    std::size_t compared = 0;
    for (std::size_t i = 0; i < t_ref.size(); ++i) {
      const bool at_event = (i > 0 && t_ref[i - 1] == t_ref[i]) || (i + 1 < t_ref.size() && t_ref[i + 1] == t_ref[i]);
      const double k = t_ref[i] / 0.0005;
      if (at_event || std::fabs(k - std::round(k)) > 1e-6) continue;
      INFO(name << " at t = " << t_ref[i]);
      CHECK(std::fabs(ours[static_cast<std::size_t>(std::lround(k))] - theirs[i]) < 1e-4 * range);
      ++compared;
    }
    CHECK(compared > 900);
  }
  // The mode flags, away from the reference's event rows (ours are within
  // the integrator's root tolerance of them): both stuck from 0.3083, the
  // bearing sliding-ready forward at its limit while the gear holds.
  std::vector<double> events;
  for (std::size_t i = 1; i < t_ref.size(); ++i)
    if (t_ref[i - 1] == t_ref[i]) events.push_back(t_ref[i]);
  REQUIRE(events.size() >= 4);
  for (const std::string name :
       {"bearingFriction.mode", "bearingFriction.startBackward", "bearingFriction.startForward", "gear.mode"}) {
    const auto ours = column(r.trajectory, name);
    const auto& theirs = ref.at(name);
    for (std::size_t i = 0; i < t_ref.size(); ++i) {
      const double k = t_ref[i] / 0.0005;
      bool near_event = std::fabs(k - std::round(k)) > 1e-6;
      for (double e : events) near_event = near_event || std::fabs(t_ref[i] - e) < 0.002;
      if (near_event) continue;
      INFO(name << " at t = " << t_ref[i]);
      CHECK(ours[static_cast<std::size_t>(std::lround(k))] == theirs[i]);
    }
  }
}

TEST_CASE("semiLinear at zero flow: the port takes the value upstream, no singular block (MLS 3.7.2.5)") {
  // tests/e2e/data/SemiLinearZeroFlow.mo: a source of enthalpy hA = 2 pushes
  // mdot = 0, 1, -1 on [0, 1), [1, 2), [2, 3) into a volume of enthalpy h
  // (M = 0.5, h(0) = 1). At zero flow the equations leave the port's h open;
  // the least-norm solution gave 0 with a warning.
  auto model = compiled_model("e2e_semilinear_zero_flow", {{kData + "SemiLinearZeroFlow.mo", "", {}, true}, {}, true});
  const auto p = model->info().default_parameters();
  const auto r = runtime::simulate(*model, {}, p, runtime::OutputGrid::uniform(0, 3, 30), tight());
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(r.warnings.empty());
  const auto& times = r.trajectory.times();
  const auto port = variable("e2e_semilinear_zero_flow", r.trajectory, p, "source.port.h");
  const auto h = column(r.trajectory, "volume.h");
  const double h2 = 2 - std::exp(-1 / 0.5);  // h at t = 2: M h' = mdot (hA - h)
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double t = times[i];
    INFO("t = " << t);
    const double expected_h = t <= 1 ? 1 : t <= 2 ? 2 - std::exp(-(t - 1) / 0.5) : h2;
    CHECK(h[i] == Approx(expected_h).margin(1e-6));
    // Upstream: the volume's h at rest (rule 1's x >= 0 branch: the
    // source's port flow is 0), the source's from t = 1 (the row at an
    // event holds the values after it), the volume's from t = 2.
    const bool from_source = t > 1 - 1e-9 && t < 2 - 1e-9;
    CHECK(port[i] == Approx(from_source ? 2.0 : h[i]).margin(1e-6));
  }
}
