// Input design and Monte Carlo on models with events (issue 15, items 3-4;
// docs/events.md): the multi-phase design's Fisher matrix, built from the
// collocated sensitivities with their jumps at the switches, against the
// Fisher matrix of finite-difference sensitivities of whole re-simulations
// under the designed input (a friction element whose right-hand side jumps;
// the bouncing ball, whose velocity is reinitialised).
#include <nlohmann/json.hpp>

#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <sstream>

#include "e2e/cli.hpp"
#include "e2e/support.hpp"

using namespace mo::e2e;
using nlohmann::json;

namespace {

json summary(const fs::path& dir) { return json::parse(slurp(dir / "summary.json")); }

Eigen::MatrixXd matrix(const json& j) {
  Eigen::MatrixXd m(static_cast<Eigen::Index>(j.size()), static_cast<Eigen::Index>(j.size()));
  for (std::size_t a = 0; a < j.size(); ++a)
    for (std::size_t b = 0; b < j.size(); ++b) m(Eigen::Index(a), Eigen::Index(b)) = j[a][b].get<double>();
  return m;
}

/// The column `name` of a CSV with a header row.
std::vector<double> column(const fs::path& csv, const std::string& name) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::size_t index = 0, k = 0;
  std::stringstream header(line);
  for (std::string f; std::getline(header, f, ','); ++k)
    if (f == name) index = k + 1;
  REQUIRE(index > 0);
  std::vector<double> out;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string f;
    for (std::size_t c = 0; c < index; ++c) std::getline(ss, f, ',');
    out.push_back(std::stod(f));
  }
  return out;
}

std::string fmt_double(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

/// What a finite-difference Fisher matrix needs: the model and how to drive it.
struct Replay {
  std::string file, model, input;  ///< input: "u=pwc:FILE" or empty
  double stop = 0;
  unsigned intervals = 0;          ///< output grid: the measurement times are its points after 0
  std::string output;              ///< measured variable
  double sigma = 0;
};

/// Σ_k S(t_k) S(t_k)ᵀ / σ² with S from central differences (relative step 1e-4:
/// result.csv holds 10 digits) of simulations at rtol 1e-11 under the designed input.
Eigen::MatrixXd fisher_by_differences(const Replay& r, const std::vector<std::pair<std::string, double>>& params,
                                      const fs::path& dir) {
  const auto n = static_cast<Eigen::Index>(params.size());
  Eigen::MatrixXd s(static_cast<Eigen::Index>(r.intervals), n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const auto& [name, value] = params[static_cast<std::size_t>(j)];
    const double h = 1e-4 * std::abs(value);
    std::vector<double> y[2];
    for (int side = 0; side < 2; ++side) {
      const fs::path out = dir / (name + (side ? "_plus" : "_minus"));
      const Run run = morun(quoted(kData + r.file) + " --class " + r.model + " --stop-time " + std::to_string(r.stop) +
                                " --intervals " + std::to_string(r.intervals) + " --rtol 1e-11 --atol 1e-12" +
                                (r.input.empty() ? "" : " --input " + quoted(r.input)) + " --set " + name + "=" +
                                fmt_double(value + (side ? h : -h)) + " -o " + quoted(out.string()),
                            dir);
      INFO(run.err);
      REQUIRE(run.status == 0);
      y[side] = column(out / "result.csv", r.output);
      REQUIRE(y[side].size() == r.intervals + 1);
    }
    for (unsigned k = 0; k < r.intervals; ++k) s(Eigen::Index(k), j) = (y[1][k + 1] - y[0][k + 1]) / (2 * h);
  }
  return s.transpose() * s / (r.sigma * r.sigma);
}

/// Runs the design study `file` into dir/out; it must end with status success.
json run_design(const std::string& file, const fs::path& dir) {
  const Run r = morun(quoted(kData + file) + " -o " + quoted((dir / "out").string()), dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  json s = summary(dir / "out");
  CHECK(s["status"] == "success");
  return s;
}

/// The collocated and the re-simulated Fisher matrix of design summary `s`
/// each within 1e-5 of the largest entry of `fd` (finite differences).
void check_fisher_against(const json& s, const Eigen::MatrixXd& fd) {
  const Eigen::MatrixXd coll = matrix(s["design"]["fisher_collocation"]);
  const Eigen::MatrixXd resim = matrix(s["design"]["fisher_resimulated"]);
  INFO("collocation\n" << coll << "\nre-simulated\n" << resim << "\nfinite differences\n" << fd);
  const double scale = fd.cwiseAbs().maxCoeff();
  CHECK((coll - fd).cwiseAbs().maxCoeff() < 1e-5 * scale);
  CHECK((resim - fd).cwiseAbs().maxCoeff() < 1e-5 * scale);
}

}  // namespace

TEST_CASE("friction: the design's Fisher matrix equals the one of finite-difference re-simulations",
          "[events][studies][design]") {
  const fs::path dir = scratch("event_design_friction");
  const json s = run_design("FrictionDesign.mop", dir);
  CHECK(s["events"]["mode_sequence_held"] == true);
  CHECK(s["events"]["mode_sequence"].size() == 1);
  CHECK(s["events"]["phases"] == 11);  // two modes, cut at the ten measurement times
  const Replay replay{"FrictionDesign.mop", "FrictionMass", "F=pwc:" + (dir / "out" / "designed_input.csv").string(),
                      2.0, 10, "x", 0.01};
  const Eigen::MatrixXd fd = fisher_by_differences(replay, {{"Fc", 0.3}, {"d", 0.5}}, dir);
  // Stated tolerance: 1e-5 of the largest entry (the collocation's own error
  // with n_e = 40, n_cp = 3 is about 1e-6 of it here).
  check_fisher_against(s, fd);
  // The sensitivity to Fc jumps at the reversal: without the jump the
  // collocated Fisher matrix would be far from the finite differences.
  CHECK(fd(0, 0) > 1.0);
}

TEST_CASE("a kick at a parameter time: the design's Fisher matrix for T equals finite differences",
          "[events][studies][design]") {
  // The sensitivity to the kick time T lives only in the jump at the kick
  // (dτ/dT = 1 from the indicator time − T); the phase boundary is tied to T
  // by the switch constraint τ − T = 0.
  const fs::path dir = scratch("event_design_kick");
  const json s = run_design("KickDesign.mop", dir);
  CHECK(s["events"]["mode_sequence_held"] == true);
  CHECK(double(s["events"]["switch_times"][0]) == Approx(0.7).margin(1e-9));
  const Replay replay{"KickDesign.mop", "KickForced", "F=pwc:" + (dir / "out" / "designed_input.csv").string(),
                      2.0, 10, "x", 0.01};
  const Eigen::MatrixXd fd = fisher_by_differences(replay, {{"T", 0.7}, {"k", 4.0}}, dir);
  check_fisher_against(s, fd);
  CHECK(fd(0, 0) > 100.0);  // T is well determined, through the jump only
}

TEST_CASE("two balls bouncing at one instant: the design's Fisher matrix equals finite differences",
          "[events][studies][design]") {
  // Two indicators cross together at the joint bounce: one switch, both
  // clauses, the sensitivity jump through both reinits with one dτ/dp.
  const fs::path dir = scratch("event_design_two_balls");
  const json s = run_design("TwoBallsDesign.mop", dir);
  CHECK(s["events"]["mode_sequence_held"] == true);
  REQUIRE(s["events"]["mode_sequence"].size() == 1);
  CHECK(s["events"]["mode_sequence"][0]["crossing_with_it"].size() == 1);
  const Replay replay{"TwoBallsDesign.mop", "TwoBallsPushed", "u=pwc:" + (dir / "out" / "designed_input.csv").string(),
                      0.8, 8, "h2", 0.01};
  const Eigen::MatrixXd fd = fisher_by_differences(replay, {{"g", 9.81}, {"e2", 0.6}}, dir);
  check_fisher_against(s, fd);
}

TEST_CASE("ball: Monte Carlo through the bounces, every run's interval covers the truth", "[events][studies]") {
  const fs::path dir = scratch("event_monte_carlo_ball");
  const Run r = morun(quoted(kData + "BallMonteCarlo.mop") + " -j 1 -o " + quoted((dir / "out").string()), dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  REQUIRE(s["cases"].size() == 1);
  const json& c = s["cases"][0];
  CHECK(c["runs"] == 4);
  CHECK(c["failures"] == 0);
  CHECK(double(c["ci_coverage"]) == 1.0);  // seeds 1-4: each 95% interval holds the true g and e
  for (const json& p : c["parameters"]) {
    INFO(p.dump());
    // The mean of 4 runs within 2 Cramér–Rao bounds of the truth (a bound of one run).
    CHECK(std::abs(double(p["bias"])) < 2.0 * double(p["cramer_rao"]));
    CHECK(double(p["std"]) < 2.0 * double(p["cramer_rao"]));
  }
  // The estimates themselves, from monte_carlo.csv: g near 9.81, e near 0.8.
  CHECK(column(dir / "out" / "monte_carlo.csv", "g").size() == 4);
  for (double g : column(dir / "out" / "monte_carlo.csv", "g")) CHECK(g == Approx(9.81).margin(0.15));
  for (double e : column(dir / "out" / "monte_carlo.csv", "e")) CHECK(e == Approx(0.8).margin(0.01));
}

TEST_CASE("friction: a multistart design solves every start through its own modes and keeps the best",
          "[events][studies][design][multistart]") {
  // starts = 3 draws three random piecewise-constant forces in [0.5, 1.5]
  // besides the initialGuess; each start records its own mode sequence and
  // phases, runs in a worker process (-j 2), and the best converged start is
  // the study's result.
  const fs::path dir = scratch("event_design_multistart");
  const Run r = morun(quoted(kData + "FrictionDesign.mop") + " --option starts=3 -j 2 -o " +
                          quoted((dir / "out").string()),
                      dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  const json& ms = s["design"]["multistart"];
  REQUIRE(ms["per_start"].size() == 4);
  CHECK(ms["per_start"][0]["origin"] == "initial_guess");
  int converged = 0;
  double best = -1e300;
  for (const json& st : ms["per_start"]) {
    INFO(st.dump());
    if (st["status"] != "success" && st["status"] != "acceptable") continue;
    ++converged;
    const double coll = st["information_collocation"], resim = st["information_resimulated"];
    // Each converged start's collocated information is its re-simulation's
    // (CVODES sensitivities with the jumps, checked against finite differences above).
    CHECK(resim == Approx(coll).epsilon(1e-4));
    best = std::max(best, coll);
  }
  CHECK(converged >= 2);
  CHECK(ms["converged"] == converged);
  CHECK(double(s["design"]["information_collocation"]) == Approx(best).epsilon(1e-12));
  const std::size_t b = ms["best_start"].get<std::size_t>() - 1;
  CHECK(double(ms["per_start"][b]["information_collocation"]) == Approx(best).epsilon(1e-12));
  CHECK(s["status"] == ms["per_start"][b]["status"]);
  CHECK(s["events"]["mode_sequence_held"] == true);
  CHECK(fs::exists(dir / "out" / "designed_input.csv"));
  CHECK(r.err.find("multistart: 4 starts") != std::string::npos);
}

TEST_CASE("friction: a multistart design whose every start fails still writes its table of starts",
          "[events][studies][design][multistart]") {
  // Fc = 2 above the largest force 1.5: the mass sticks at v = 0, a sliding
  // mode that no start's guess simulates through. The summary says why for
  // each start; there is no design to write.
  const fs::path dir = scratch("event_design_multistart_fails");
  const Run r = morun(quoted(kData + "FrictionDesign.mop") + " --option starts=2 --set Fc=2 -o " +
                          quoted((dir / "out").string()),
                      dir);
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("multistart: 3 starts, 0 converged") != std::string::npos);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "error");
  CHECK_THAT(s["message"].get<std::string>(), Catch::StartsWith("no start of the design gave a result (start 1: "));
  const json& ms = s["design"]["multistart"];
  CHECK(ms["best_start"].is_null());
  CHECK(ms["converged"] == 0);
  REQUIRE(ms["per_start"].size() == 3);
  for (const json& st : ms["per_start"]) {
    CHECK(st["status"] == "error");
    CHECK_THAT(st["error"].get<std::string>(), Catch::StartsWith("the simulation of the guess failed: "));
  }
  CHECK_FALSE(fs::exists(dir / "out" / "designed_input.csv"));
}

TEST_CASE("sample() ticks that kick the oscillator: the design's Fisher matrix equals finite differences",
          "[events][studies][design]") {
  // Three ticks inside the horizon are timed switches: fixed times, the
  // sensitivity states jump by the reinit's tangent only.
  const fs::path dir = scratch("event_design_sampled_kick");
  const json s = run_design("SampledKickDesign.mop", dir);
  REQUIRE(s["events"]["mode_sequence"].size() == 3);
  CHECK(s["events"]["mode_sequence"][1]["time_event"] == true);
  CHECK(double(s["events"]["mode_sequence"][1]["time"]) == Approx(0.35 + 0.7).margin(1e-15));
  const Replay replay{"SampledKickDesign.mop", "SampledKick", "F=pwc:" + (dir / "out" / "designed_input.csv").string(),
                      2.0, 10, "x", 0.01};
  const Eigen::MatrixXd fd = fisher_by_differences(replay, {{"k", 4.0}, {"J", 0.5}}, dir);
  check_fisher_against(s, fd);
}

TEST_CASE("a set point designed through a sampled controller: the Fisher matrix equals finite differences",
          "[events][studies][design]") {
  // The held control and its sensitivities to a and b are unknowns of each
  // phase, set at each tick from the tangent of kp·(r − x); the samples fall
  // on the ticks.
  const fs::path dir = scratch("event_design_sampled_loop");
  const json s = run_design("SampledDesign.mop", dir);
  CHECK(s["events"]["mode_sequence"].size() == 9);
  const Replay replay{"SampledDesign.mop", "SampledPlant", "r=pwc:" + (dir / "out" / "designed_input.csv").string(),
                      2.0, 10, "x", 0.01};
  const Eigen::MatrixXd fd = fisher_by_differences(replay, {{"a", 1.5}, {"b", 2.0}}, dir);
  check_fisher_against(s, fd);
}

TEST_CASE("Monte Carlo through a sampled controller: the Cramer-Rao bound through the held control",
          "[events][studies]") {
  // The bound is that of the Fisher matrix from central differences of the
  // exact piecewise-exponential solution (SampledEstimate's 20 samples, σ = 0.01).
  const fs::path dir = scratch("event_monte_carlo_sampled");
  const Run r = morun(quoted(kData + "SampledMonteCarlo.mop") + " -j 1 -o " + quoted((dir / "out").string()), dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  REQUIRE(s["cases"].size() == 1);
  const json& c = s["cases"][0];
  CHECK(c["runs"] == 4);
  CHECK(c["failures"] == 0);
  const double bound[2] = {0.0433128520, 0.0426050857};
  for (std::size_t i = 0; i < 2; ++i) {
    const json& p = c["parameters"][i];
    INFO(p.dump());
    CHECK(double(p["cramer_rao"]) == Approx(bound[i]).epsilon(1e-6));
    CHECK(std::abs(double(p["bias"])) < 2.0 * bound[i]);
  }
  CHECK(s["status"] == "success");
}

TEST_CASE("Monte Carlo whose every run fails says so: no statistics of an empty sample and exit 1",
          "[events][studies]") {
  // One Ipopt iteration per estimate: every run ends at the iteration limit.
  // The summary used to give mean 0, bias −truth and exit 0.
  const fs::path dir = scratch("event_monte_carlo_failed");
  const Run r = morun(quoted(kData + "SampledMonteCarlo.mop") + " -j 1 --option max_iter=1 -o " +
                          quoted((dir / "out").string()),
                      dir);
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("case 1: every run failed (iteration_limit ×4)") != std::string::npos);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "failed");
  const json& c = s["cases"][0];
  CHECK(c["runs"] == 0);
  CHECK(c["failures"] == 4);
  CHECK(c["failed_with"]["iteration_limit"] == 4);
  CHECK(c["ci_coverage"].is_null());
  for (const json& p : c["parameters"]) {
    INFO(p.dump());
    CHECK(p["mean"].is_null());
    CHECK(p["bias"].is_null());
    CHECK(p["std"].is_null());
    CHECK(p["cramer_rao"].is_number());  // from the truth's sensitivities, not from the runs
  }
}

TEST_CASE("a kick period designed through ticks that move with it: the Fisher matrix equals finite differences",
          "[events][studies][design]") {
  // Tick n of sample(0.35, P) moves by dτ/dP = n: the sensitivity states jump
  // with that η at each kick (δstart + n·δinterval of the tick).
  const fs::path dir = scratch("event_design_sampled_period");
  const json s = run_design("SampledPeriodDesign.mop", dir);
  REQUIRE(s["events"]["mode_sequence"].size() == 3);
  const Replay replay{"SampledPeriodDesign.mop", "PeriodicKick", "F=pwc:" + (dir / "out" / "designed_input.csv").string(),
                      2.0, 10, "x", 0.01};
  const Eigen::MatrixXd fd = fisher_by_differences(replay, {{"P", 0.7}, {"J", 0.5}}, dir);
  check_fisher_against(s, fd);
  CHECK(fd(0, 0) > 1000.0);  // P is determined through the moving kicks only
}
