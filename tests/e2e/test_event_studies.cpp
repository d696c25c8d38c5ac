// Optimal control on models with events by multi-phase collocation (issue 15,
// item 3; docs/events.md): the ball's gravity that reaches h(0.8) = 0.5 with
// the bounce, checked against the analytic solution and the re-simulation; an
// input on the same ball; a diode-like if-expression (7 phases) and a
// discrete brake mode set by a when-clause; a mode sequence that changes at the optimum and is
// rebuilt; an estimation of g and e from heights simulated with known values
// (recovered); Zeno behaviour and a when-condition it does not take, refused at
// the when-clause.
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

#include "e2e/cli.hpp"
#include "e2e/support.hpp"

using namespace mo::e2e;
using nlohmann::json;

namespace {

json summary(const fs::path& dir) { return json::parse(slurp(dir / "summary.json")); }

/// Rows of a CSV (after its header) as numbers.
std::vector<std::vector<double>> rows(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<double>> out;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<double> row;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) row.push_back(std::stod(f));
    out.push_back(std::move(row));
  }
  return out;
}

/// h(t) of the ball dropped from h = 1 with one bounce (t after the bounce).
double ball_height(double g, double e, double t) {
  const double tau = std::sqrt(2.0 / g), dt = t - tau;
  return e * std::sqrt(2.0 * g) * dt - 0.5 * g * dt * dt;
}

/// The estimation's Fisher matrix in summary `s` equals `expected` to 1e-6 (relative).
void check_fisher(const json& s, const std::vector<std::vector<double>>& expected) {
  for (std::size_t i = 0; i < expected.size(); ++i)
    for (std::size_t j = 0; j < expected[i].size(); ++j)
      CHECK(double(s["fisher"][i][j]) == Approx(expected[i][j]).epsilon(1e-6));
}

Run run_study(const std::string& file, const fs::path& out, const fs::path& dir) {
  return morun(quoted(kData + file) + " -o " + quoted(out.string()), dir);
}

}  // namespace

TEST_CASE("ball: the gravity that reaches h(0.8) = 0.5 bounces, as the analytic solution does",
          "[events][studies]") {
  const fs::path dir = scratch("event_study_gravity");
  const Run r = run_study("BallGravity.mop", dir / "out", dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "success");
  CHECK(s["events"]["phases"] == 2);
  CHECK(s["events"]["mode_sequence_held"] == true);
  const double g = s["parameters"]["g"];
  // The optimum with the bounce: h(0.8) = 0.5 after it, g ≈ 6.353 (not 1.5625 without it).
  CHECK(g == Approx(6.3531).margin(1e-3));
  CHECK(ball_height(g, 0.8, 0.8) == Approx(0.5).margin(1e-6));
  const double tau = s["events"]["switch_times"][0];
  CHECK(tau == Approx(std::sqrt(2.0 / g)).margin(1e-7));
  // The re-simulation (CVODES with the event) agrees with the collocation.
  CHECK(s["events"]["resimulated_mode_sequence"].size() == 1);
  CHECK(double(s["events"]["max_relative_state_difference"]) < 1e-6);
  CHECK(double(s["events"]["max_switch_time_difference"]) < 1e-6);
  const auto traj = rows(dir / "out" / "trajectories.csv");
  REQUIRE(!traj.empty());
  CHECK(traj.back()[0] == Approx(0.8));
  CHECK(traj.back()[1] == Approx(0.5).margin(1e-6));
  const auto resim = rows(dir / "out" / "resimulated.csv");
  REQUIRE(!resim.empty());
  CHECK(resim.back()[1] == Approx(0.5).margin(1e-6));
}

TEST_CASE("a time event at a free parameter time: the switching time is the parameter", "[events][studies]") {
  // when time >= T: the switch constraint reads tau - T = 0 (linear, exact),
  // so the phase boundary moves with the free T; analytic optimum T = 0.7601269.
  const fs::path dir = scratch("event_study_kick_time");
  const Run r = run_study("KickTime.mop", dir / "out", dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "success");
  CHECK(s["events"]["phases"] == 2);
  const double T = s["parameters"]["T"];
  const double analytic = (4.0 - (M_PI - std::asin(2.0 * (-0.5 - std::cos(4.0)) / 0.5))) / 2.0;
  CHECK(T == Approx(analytic).margin(1e-6));
  CHECK(double(s["events"]["switch_times"][0]) == Approx(T).margin(1e-9));
  CHECK(double(s["events"]["max_relative_state_difference"]) < 1e-5);
  CHECK(double(s["events"]["max_switch_time_difference"]) < 1e-7);
}

TEST_CASE("two indicators crossing at one instant make one switch firing both clauses", "[events][studies]") {
  // Two balls dropped together: h1 and h2 cross at once. One phase boundary
  // imposes the first indicator = 0, flips both and applies both reinits; the
  // re-simulation sees both cross together again at the optimum.
  const fs::path dir = scratch("event_study_two_balls");
  const Run r = run_study("TwoBalls.mop", dir / "out", dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "success");
  CHECK(s["events"]["phases"] == 2);
  REQUIRE(s["events"]["mode_sequence"].size() == 1);
  CHECK(s["events"]["mode_sequence"][0]["when_clauses"].size() == 2);
  CHECK(s["events"]["mode_sequence"][0]["crossing_with_it"].size() == 1);
  CHECK(s["events"]["resimulated_mode_sequence"][0]["crossing_with_it"].size() == 1);
  const double g = s["parameters"]["g"];
  CHECK(g == Approx(6.3531).margin(1e-3));
  CHECK(ball_height(g, 0.8, 0.8) == Approx(0.5).margin(1e-6));
  CHECK(double(s["events"]["switch_times"][0]) == Approx(std::sqrt(2.0 / g)).margin(1e-7));
  CHECK(double(s["events"]["max_relative_state_difference"]) < 1e-6);
  // Ball 2 (e = 0.6) at 0.8, from the trajectories: columns time, h1, v1, h2, v2.
  const auto traj = rows(dir / "out" / "trajectories.csv");
  REQUIRE(!traj.empty());
  CHECK(traj.back()[3] == Approx(ball_height(g, 0.6, 0.8)).margin(1e-6));
}

TEST_CASE("ball pushed by an input: each phase has its own controls, the re-simulation bounces too",
          "[events][studies]") {
  const fs::path dir = scratch("event_study_input");
  const Run r = run_study("BallControl.mop", dir / "out", dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "success");
  CHECK(s["events"]["phases"] == 2);
  CHECK(s["events"]["mode_sequence_held"] == true);
  CHECK(double(s["events"]["max_relative_state_difference"]) < 1e-6);
  CHECK(s["collocation"]["n_e"] == 40);  // 20 elements per phase
  const auto resim = rows(dir / "out" / "resimulated.csv");
  REQUIRE(!resim.empty());
  CHECK(resim.back()[1] == Approx(0.5).margin(1e-6));
}

TEST_CASE("ball: the optimum bounces twice, the mode sequence is rebuilt and solved again",
          "[events][studies]") {
  const fs::path dir = scratch("event_study_rebuild");
  const Run r = run_study("BallHeavier.mop", dir / "out", dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "success");
  CHECK(s["events"]["attempts"] == 2);
  CHECK(s["events"]["phases"] == 3);
  CHECK(double(s["parameters"]["g"]) == Approx(30.0));
  CHECK(double(s["events"]["max_relative_state_difference"]) < 1e-6);
  CHECK(r.err.find("attempt 1: success; re-simulated: h falls through 0 at t = 0.258199, h falls through 0 at t = 0.671317") !=
        std::string::npos);
}

TEST_CASE("Zeno behaviour and a compound when-condition are refused at the when-clause", "[events][studies]") {
  const fs::path dir = scratch("event_study_refused");
  const Run zeno = run_study("BallZeno.mop", dir / "zeno", dir);
  INFO(zeno.err);
  CHECK(zeno.status == 1);
  CHECK(zeno.err.find("BallZeno.mop:12:3: error:") != std::string::npos);
  CHECK(zeno.err.find("chattering or Zeno") != std::string::npos);
  CHECK(!fs::exists(dir / "zeno" / "summary.json"));
  const Run compound = run_study("BallCompound.mop", dir / "compound", dir);
  INFO(compound.err);
  CHECK(compound.status == 1);
  CHECK(compound.err.find("BallCompound.mop:11:3: error: when v < 0 and h < 0") != std::string::npos);
  CHECK(!fs::exists(dir / "compound" / "summary.json"));
}

TEST_CASE("relations of the equations and discrete modes are frozen per phase", "[events][studies]") {
  const fs::path dir = scratch("event_study_modes");
  SECTION("a diode-like if-expression switches six times") {
    const Run r = run_study("DiodeControl.mop", dir / "diode", dir);
    INFO(r.err);
    REQUIRE(r.status == 0);
    const json s = summary(dir / "diode");
    CHECK(s["status"] == "success");
    CHECK(s["events"]["phases"] == 7);
    CHECK(s["events"]["mode_sequence_held"] == true);
    CHECK(double(s["events"]["max_relative_state_difference"]) < 1e-4);
    CHECK(double(s["events"]["max_switch_time_difference"]) < 1e-6);
    const auto resim = rows(dir / "diode" / "resimulated.csv");
    REQUIRE(!resim.empty());
    CHECK(resim.back()[1] == Approx(0.1).margin(1e-5));  // vc(3) of CVODES at the optimum
  }
  SECTION("a brake mode set by a when-clause and read by an if-expression") {
    const Run r = run_study("BrakeControl.mop", dir / "brake", dir);
    INFO(r.err);
    REQUIRE(r.status == 0);
    const json s = summary(dir / "brake");
    CHECK(s["status"] == "success");
    CHECK(s["events"]["phases"] == 2);
    CHECK(double(s["events"]["max_relative_state_difference"]) < 1e-4);
    const auto resim = rows(dir / "brake" / "resimulated.csv");
    REQUIRE(!resim.empty());
    CHECK(resim.back()[1] == Approx(2.5).margin(1e-5));  // x(4) of CVODES at the optimum
  }
}

TEST_CASE("estimation through two bounces recovers g and e from simulated heights", "[events][studies]") {
  const fs::path dir = scratch("event_study_estimation");
  const Run r = run_study("BallEstimate.mop", dir / "out", dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "success");
  CHECK(s["events"]["mode_sequence_held"] == true);
  CHECK(s["events"]["resimulated_mode_sequence"].size() == 2);
  CHECK(double(s["events"]["max_relative_state_difference"]) < 1e-6);
  REQUIRE(s["estimates"].size() == 2);
  CHECK(s["estimates"][0]["name"] == "g");
  CHECK(double(s["estimates"][0]["estimate"]) == Approx(9.81).margin(1e-6));
  CHECK(s["estimates"][1]["name"] == "e");
  CHECK(double(s["estimates"][1]["estimate"]) == Approx(0.8).margin(1e-6));
  // Noise-free data: χ² and the standard errors (CVODES sensitivities through the bounces) vanish.
  CHECK(double(s["estimates"][0]["standard_error"]) < 1e-6);
  CHECK(fs::exists(dir / "out" / "fit.csv"));
}

TEST_CASE("estimation through a sampled controller: a held value per phase and statistics through it",
          "[events][studies]") {
  // sampled_loop.csv is the exact solution for a = 1.5, b = 2. The Fisher
  // matrix below is from central differences of that exact solution (step
  // 1e-6, σ = 0.01): the statistics' sensitivities through the held uh.
  const fs::path dir = scratch("event_study_sampled_estimation");
  const Run r = run_study("SampledEstimate.mop", dir / "out", dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "success");
  CHECK(s["events"]["phases"] == 20);  // 10 ticks inside (0, 2), every other one on a sample time
  CHECK(s["events"]["mode_sequence"].size() == 9);
  CHECK(s["events"]["mode_sequence"][0]["time_event"] == true);
  CHECK(double(s["parameters"][0]["estimate"]) == Approx(1.5).epsilon(1e-7));
  CHECK(double(s["parameters"][1]["estimate"]) == Approx(2.0).epsilon(1e-7));
  check_fisher(s, {{3644.7348878, -3423.6254360}, {-3423.6254360, 3766.8351925}});
}

TEST_CASE("optimal control through a sampled controller reaches the least-squares optimum of the held values",
          "[events][studies]") {
  // The reference is the exact least-squares choice of the ten held values
  // uh_k on [0.2k, 0.2k + 0.2) for ∫(x − 1)² (SampledTrack.mop): 0.0529149035,
  // with r = uh_0/kp + x(0) = 4.58136 at t = 0.
  const fs::path dir = scratch("event_study_sampled_control");
  const Run r = run_study("SampledTrack.mop", dir / "out", dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "success");
  CHECK(s["events"]["phases"] == 10);
  CHECK(double(s["objective"]) == Approx(0.0529149035).epsilon(1e-6));
  const auto traj = rows(dir / "out" / "trajectories.csv");
  REQUIRE(!traj.empty());
  CHECK(traj.front()[2] == Approx(4.58136).epsilon(1e-5));
}

TEST_CASE("estimation through the MSL's ZeroOrderHold: held at initialisation and at each tick",
          "[events][studies]") {
  const std::string shared = shared_third_party_dir();
  if (shared.empty()) {
    WARN("SKIPPED: no ../shared/third_party (set MO_SHARED_DIR)");
    return;
  }
  const ModelicaPath msl(shared + "/third_party/msl-3.2.2");
  const fs::path dir = scratch("event_study_msl_hold");
  const Run r = run_study("MslSampledEstimate.mop", dir / "out", dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "success");
  CHECK(double(s["parameters"][0]["estimate"]) == Approx(2.0).epsilon(1e-7));  // k
  CHECK(double(s["parameters"][1]["estimate"]) == Approx(0.4).epsilon(1e-7));  // plant.T
  // Central differences of the exact solution (msl_sampled_loop.csv), σ = 0.01.
  check_fisher(s, {{4109.8693735, -9627.1156945}, {-9627.1156945, 38256.201990}});
}

TEST_CASE("the sample period estimated through ticks that move with it", "[events][studies]") {
  // Each tick is a phase boundary at τ = k·T. The Fisher matrix below is
  // from central differences of the exact solution (a = 1.5, T = 0.2; step
  // 1e-7, σ = 0.01). Samples on ticks that move are refused.
  const fs::path dir = scratch("event_study_sampled_period");
  const Run r = run_study("SampledPeriod.mop", dir / "out", dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "success");
  CHECK(double(s["parameters"][0]["estimate"]) == Approx(1.5).epsilon(1e-7));
  CHECK(double(s["parameters"][1]["estimate"]) == Approx(0.2).epsilon(1e-7));
  CHECK(double(s["events"]["switch_times"][8]) == Approx(1.8).epsilon(1e-7));
  check_fisher(s, {{3500.73509, -1378.84962}, {-1378.84962, 2807.81326}});
  const Run on_ticks = run_study("SampledPeriodOnTicks.mop", dir / "on_ticks", dir);
  INFO(on_ticks.err);
  CHECK(on_ticks.status == 1);
  CHECK(on_ticks.err.find("moves with an estimated parameter and lies on a sample time") != std::string::npos);
}

TEST_CASE("estimation through a value held at a state event: the crossing time free, the held value an unknown",
          "[events][studies]") {
  // The Fisher matrix below is from central differences of the exact
  // solution (a = 1, c = 0.55; step 1e-7, σ = 0.01).
  const fs::path dir = scratch("event_study_latched_slope");
  const Run r = run_study("LatchedSlope.mop", dir / "out", dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "success");
  REQUIRE(s["events"]["mode_sequence"].size() == 1);
  CHECK(s["events"]["mode_sequence"][0]["indicator"] == "x - c");
  CHECK(double(s["parameters"][0]["estimate"]) == Approx(1.0).epsilon(1e-7));
  CHECK(double(s["parameters"][1]["estimate"]) == Approx(0.55).epsilon(1e-7));
  CHECK(double(s["events"]["switch_times"][0]) == Approx(0.55).epsilon(1e-7));
  check_fisher(s, {{141901.48439, 2131.2499758}, {2131.2499758, 8500.0000055}});
}
