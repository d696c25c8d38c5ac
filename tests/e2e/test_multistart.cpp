// Multistart input design (issue 11.3): random starts that find a better
// local optimum than the first start, reproducible with a seed, the same
// with one process, two worker processes and two MPI ranks; and the pieces
// underneath (the clustering of optima, the JSON a worker returns, the
// seeded draws).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "e2e/cli.hpp"
#include "e2e/support.hpp"
#include "design_result_json.hpp"
#include "multistart.hpp"
#include "multistart_starts.hpp"

using namespace mo::e2e;
using nlohmann::json;

namespace {

const std::string kStudy = quoted(std::string(MO_TEST_DATA_DIR) + "/MultistartDesign.mop");

json summary(const fs::path& dir) { return json::parse(slurp(dir / "summary.json")); }

/// The multistart study with extra arguments; its design.multistart block.
json multistart(const std::string& name, const std::string& args) {
  const fs::path dir = scratch(name);
  const Run r = morun(kStudy + " -o " + quoted((dir / "out").string()) + " " + args, dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  json s = summary(dir / "out");
  REQUIRE(s["design"].contains("multistart"));
  CHECK(r.err.find("local optima") != std::string::npos);
  s["design"]["multistart"]["designed_input"] = slurp(dir / "out" / "designed_input.csv");
  return s["design"]["multistart"];
}

/// Two runs found the same starts, values and best design.
void check_same(const json& a, const json& b) {
  REQUIRE(a["per_start"].size() == b["per_start"].size());
  for (std::size_t k = 0; k < a["per_start"].size(); ++k) {
    INFO("start " << k + 1);
    CHECK(a["per_start"][k]["label"] == b["per_start"][k]["label"]);
    CHECK(a["per_start"][k]["status"] == b["per_start"][k]["status"]);
    CHECK(a["per_start"][k]["iterations"] == b["per_start"][k]["iterations"]);
    CHECK(a["per_start"][k]["information_collocation"] == b["per_start"][k]["information_collocation"]);
  }
  CHECK(a["best_start"] == b["best_start"]);
  CHECK(a["local_optima"] == b["local_optima"]);
  CHECK(a["designed_input"] == b["designed_input"]);
}

}  // namespace

TEST_CASE("multistart: random starts find a better local optimum than the first start") {
  const json m = multistart("multistart_better", "-j 1");
  REQUIRE(m["starts"] == 7);  // the initial guess and starts = 6 random ones
  CHECK(m["per_start"][0]["origin"] == "initial_guess");
  CHECK(m["per_start"][1]["origin"] == "random");
  REQUIRE(m["local_optima"].size() >= 2);
  const double first = m["per_start"][0]["information_collocation"].get<double>();
  const double best = m["local_optima"][0]["information_collocation"].get<double>();
  CHECK(best > 1.05 * first);
  CHECK(m["best_start"].get<int>() > 1);
  CHECK(m["reached_best"].get<int>() >= 1);
  CHECK(m["local_optima"][0]["information_resimulated"].get<double>() == Approx(best).epsilon(1e-3));
  int counted = 0;
  for (const auto& o : m["local_optima"]) counted += o["count"].get<int>();
  CHECK(counted == m["converged"].get<int>());
}

TEST_CASE("multistart: a seed makes the random starts reproducible, and -j 1 equals -j 2") {
  const json one = multistart("multistart_j1", "-j 1");
  const json two = multistart("multistart_j2", "-j 2");
  check_same(one, two);
  const json again = multistart("multistart_j2_again", "-j 2");
  check_same(two, again);
  const json other = multistart("multistart_seed", "-j 2 --option seed=4");
  CHECK(other["per_start"][1]["label"] != two["per_start"][1]["label"]);
  CHECK(other["per_start"][1]["information_collocation"] != two["per_start"][1]["information_collocation"]);
}

namespace {
/// mpirun with the environment of the tests. OpenMPI leaks in MPI_Init from
/// plugins it unloads at exit (LeakSanitizer cannot even name them), so leak
/// checks are off for the ranks; every other test checks morun's own leaks.
std::string mpirun_prefix() {
  return "XDG_CACHE_HOME=" + quoted(std::string(MO_TEST_CACHE_DIR) + "/morun-test-cache") +
         " ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0\""
         " mpirun --allow-run-as-root --oversubscribe -n 2 ";
}
}  // namespace

TEST_CASE("multistart: mpirun -n 2 splits the starts and finds what one process finds") {
#ifndef MO_TEST_MPI
  WARN("SKIPPED: morun was built without MPI (libopenmpi-dev not found by CMake)");
  return;
#else
  if (std::system("command -v mpirun >/dev/null 2>&1") != 0) {
    WARN("SKIPPED: mpirun is not installed");
    return;
  }
  const json one = multistart("multistart_mpi_ref", "-j 1");
  const fs::path dir = scratch("multistart_mpi");
  const std::string cmd =
      mpirun_prefix() + quoted(kMorun) + " " + kStudy + " -o " +
      quoted((dir / "out").string()) + " >" + quoted((dir / "mpirun.txt").string()) + " 2>&1";
  const int status = std::system(cmd.c_str());
  INFO(slurp(dir / "mpirun.txt"));
  REQUIRE(status == 0);
  json s = summary(dir / "out");
  REQUIRE(s["design"].contains("multistart"));
  json m = s["design"]["multistart"];
  m["designed_input"] = slurp(dir / "out" / "designed_input.csv");
  check_same(one, m);
  CHECK(fs::exists(dir / "out" / "rank_1.log"));

  // A Monte-Carlo study split across the ranks writes the runs of one process.
  const std::string data = std::string(MO_TEST_DATA_DIR) + "/";
  const std::string mc = quoted(data + "DecayDesign.mop") + " -L " + quoted(data + "Decay.mo") +
                         " --class DecayEstimate --option task=monte_carlo --option seeds=4"
                         " --option 'outputs={x}' --option measurements=20";
  const Run ref = morun(mc + " -j 1 -o " + quoted((dir / "mc1").string()), dir);
  REQUIRE(ref.status == 0);
  const std::string mpi_mc = mpirun_prefix() + quoted(kMorun) + " " + mc +
                             " -o " + quoted((dir / "mc2").string()) + " >/dev/null 2>&1";
  REQUIRE(std::system(mpi_mc.c_str()) == 0);
  CHECK(slurp(dir / "mc1" / "monte_carlo.csv") == slurp(dir / "mc2" / "monte_carlo.csv"));
#endif
}

TEST_CASE("multistart: optima are clustered by relative tolerance, best first") {
  using mo::tools::StartOutcome;
  auto start = [](std::size_t k, double v, bool ok) {
    StartOutcome s;
    s.index = k, s.converged = ok, s.information_collocation = v, s.information_resimulated = v;
    return s;
  };
  const std::vector<StartOutcome> starts{start(0, 10.0, true), start(1, 20.0, true), start(2, 20.0005, true),
                                         start(3, 99.0, false), start(4, 10.00001, true)};
  const auto optima = mo::tools::cluster_optima(starts, 1e-4);
  REQUIRE(optima.size() == 2);
  CHECK(optima[0].information_collocation == 20.0005);
  CHECK(optima[0].starts == std::vector<std::size_t>{2, 1});
  CHECK(optima[1].starts == std::vector<std::size_t>{4, 0});
  CHECK(mo::tools::cluster_optima(starts, 1e-7).size() == 4);
}

TEST_CASE("multistart: a design result survives the worker's JSON exactly, NaN included") {
  mo::runtime::InputDesignResult r;
  r.optimization.status = mo::runtime::OptimizationStatus::stalled;
  r.optimization.objective = -0.1 / 3.0;
  r.optimization.control_values = {{0.1, std::nan("")}, {1e-300, -INFINITY}};
  r.optimization.trajectories = mo::runtime::ResultTable({"x", "u"});
  r.optimization.trajectories.add_row(0.0, std::vector<double>{1.0 / 7.0, 2.0});
  r.optimization.trajectories.add_row(0.5, std::vector<double>{M_PI, -0.0});
  r.fisher_collocation = Eigen::MatrixXd{{1.0 / 3.0, 2.0}, {2.0, 5.0}};
  r.information_resimulated = std::nan("");
  const auto back = mo::tools::design_result_from_json(json::parse(mo::tools::design_result_to_json(r).dump()));
  CHECK(back.optimization.status == r.optimization.status);
  CHECK(back.optimization.objective == r.optimization.objective);
  CHECK(back.optimization.control_values[0][0] == 0.1);
  CHECK(std::isnan(back.optimization.control_values[0][1]));
  CHECK(back.optimization.control_values[1][1] == -INFINITY);
  CHECK(back.optimization.trajectories.at(1, 0) == M_PI);
  CHECK(back.optimization.trajectories.at(0, 0) == 1.0 / 7.0);
  CHECK(back.fisher_collocation == r.fisher_collocation);
  CHECK(std::isnan(back.information_resimulated));
}

TEST_CASE("multistart: random starts are uniform per control interval, seeded, bounded") {
  mo::runtime::OptimalControlProblem ocp;
  ocp.t0 = 0, ocp.tf = 4;
  ocp.collocation.n_e = 8;
  mo::runtime::FreeControl c;
  c.bounds = {-2.0, 3.0};
  c.blocking_factors = {2, 2, 4};
  ocp.controls = {c};
  CHECK(mo::tools::control_interval_times(ocp, c) == std::vector<double>{0.0, 1.0, 2.0});
  mo::runtime::ModelInfo info;
  info.inputs.push_back({});
  info.inputs[0].name = "u";
  auto values = [&](int seed, std::size_t r) {
    const auto s = mo::tools::random_start(ocp, info, seed, r);
    std::vector<double> v;
    for (double t : {0.5, 1.5, 3.0}) v.push_back(s.guesses[0]->value(t));
    return v;
  };
  CHECK(values(1, 0) == values(1, 0));
  CHECK(values(1, 0) != values(1, 1));
  CHECK(values(1, 0) != values(2, 0));
  double lo = 1e9, hi = -1e9;
  for (std::size_t r = 0; r < 200; ++r)
    for (double v : values(5, r)) lo = std::min(lo, v), hi = std::max(hi, v);
  CHECK(lo >= -2.0);
  CHECK(lo < -1.9);
  CHECK(hi < 3.0);
  CHECK(hi > 2.9);
  c.bounds.hi = INFINITY;
  ocp.controls = {c};
  CHECK_THROWS_WITH(mo::tools::random_start(ocp, info, 1, 0), Catch::Contains("'u' needs a finite min and max"));
}

TEST_CASE("multistart: a Monte-Carlo study gives the same runs with -j 1 and -j 2") {
  const std::string data = std::string(MO_TEST_DATA_DIR) + "/";
  const std::string args = quoted(data + "DecayDesign.mop") + " -L " + quoted(data + "Decay.mo") +
                           " --class DecayEstimate --option task=monte_carlo --option seeds=4"
                           " --option 'outputs={x}' --option measurements=20";
  std::string csv[2];
  for (int j = 1; j <= 2; ++j) {
    const fs::path dir = scratch("multistart_mc_j" + std::to_string(j));
    const Run r = morun(args + " -j " + std::to_string(j) + " -o " + quoted((dir / "out").string()), dir);
    INFO(r.err);
    REQUIRE(r.status == 0);
    csv[j - 1] = slurp(dir / "out" / "monte_carlo.csv");
  }
  CHECK(std::count(csv[0].begin(), csv[0].end(), '\n') == 5);  // header and four runs
  CHECK(csv[0] == csv[1]);
}
