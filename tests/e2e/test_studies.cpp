// morun on study files (issues 5 and 6): a plain JModelica .mop optimal
// control problem against its analytic optimum, and a reduced cart-pendulum
// study — design (constraints met on re-simulation), data, estimation (the
// truth inside the confidence interval), a Monte-Carlo run — with the numbers
// read back from summary.json. Bad study options are rejected.
#include <nlohmann/json.hpp>

#include <sstream>

#include "e2e/cli.hpp"
#include "e2e/support.hpp"

using namespace mo::e2e;
using nlohmann::json;

namespace {

const std::string kCart = kModelica + "CartPendulum/";
const std::string kOde = quoted(kCart + "CartPendulumODE.mo");

json summary(const fs::path& dir) { return json::parse(slurp(dir / "summary.json")); }

/// The last row of a CSV as numbers.
std::vector<double> last_row(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  std::vector<double> out;
  std::stringstream ss(last);
  for (std::string f; std::getline(ss, f, ',');) out.push_back(std::stod(f));
  return out;
}

/// The reduced design shared by the cart-pendulum cases (40 elements).
fs::path designed(const fs::path& dir) {
  const fs::path out = dir / "design";
  const Run r = morun(quoted(kCart + "CartPendulumDesign.opt") + " -L " + kOde + " -o " +
                          quoted(out.string()) +
                          " --option n_e=40 --option measurements=40 --option 'starts={\"const:0\"}'",
                      dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  return out;
}

}  // namespace

TEST_CASE("studies: a JModelica .mop minimum-energy problem meets its analytic optimum") {
  const fs::path dir = scratch("study_mop");
  const Run r = morun(quoted(std::string(MO_TEST_DATA_DIR) + "/DoubleIntegrator.mop") + " -o " +
                          quoted((dir / "out").string()),
                      dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json s = summary(dir / "out");
  CHECK(s["status"] == "success");
  // One control value per element: 12 d²/(T³ − h²T) with d = T = 1, h = 1/20.
  CHECK(s["objective"].get<double>() == Approx(12.0 / (1.0 - 1.0 / 400.0)).epsilon(1e-6));
  CHECK(s["resimulation"]["max_state_difference"].get<double>() < 1e-6);
  const auto final_state = last_row(dir / "out" / "trajectories.csv");  // time, x, v, u
  CHECK(final_state[1] == Approx(1.0).margin(1e-8));
  CHECK(final_state[2] == Approx(0.0).margin(1e-8));
}

TEST_CASE("studies: reduced cart-pendulum design, estimation and Monte Carlo") {
  const fs::path dir = scratch("study_cart");
  const fs::path design = designed(dir);
  const json d = summary(design);
  CHECK(d["resimulation"]["max_bound_violation"].get<double>() < 1e-3);
  const double info = d["design"]["information_resimulated"].get<double>();
  CHECK(info == Approx(d["design"]["information_collocation"].get<double>()).epsilon(0.01));
  CHECK(info > 100);
  const auto end = last_row(design / "trajectories.csv");  // time, x, phi, v, w, ...
  CHECK(end[1] == Approx(0.5).margin(1e-6));
  CHECK(std::abs(end[2]) < 1e-6);

  const std::string input = "F=pwc:" + (design / "designed_input.csv").string();
  const fs::path data = dir / "data";
  Run r = morun(kOde + " -c CartPendulumODE --stop-time 5 --intervals 200 --rtol 1e-10 --atol 1e-12 "
                       "--measure y_x,y_phi --noise 0.01 --seed 3 --input " + quoted(input) +
                    " -o " + quoted(data.string()),
                dir);
  INFO(r.err);
  REQUIRE(r.status == 0);

  const fs::path est = dir / "estimate";
  r = morun(quoted(kCart + "CartPendulumEstimate.opt") + " -L " + kOde + " -o " + quoted(est.string()) +
                " --option n_e=100 --option " + quoted("data={\"" + (data / "measurements.csv").string() + "\"}") +
                " --option " + quoted("inputs={\"" + input + "\"}"),
            dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json e = summary(est)["estimates"][0];
  CHECK(e["name"] == "m2");
  CHECK(e["ci"][0].get<double>() < 1.0);
  CHECK(e["ci"][1].get<double>() > 1.0);
  CHECK(std::abs(e["estimate"].get<double>() - 1.0) < 0.1);
  CHECK(fs::exists(est / "fit.csv"));

  const fs::path mc = dir / "monte_carlo";
  r = morun(quoted(kCart + "CartPendulumMonteCarlo.opt") + " -L " + kOde + " -o " + quoted(mc.string()) +
                " --option seeds=4 --option n_e=100 --option measurements=200 --option " +
                quoted("inputs={\"" + input + "\", \"F=sine:3,1\"}"),
            dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json cases = summary(mc)["cases"];
  REQUIRE(cases.size() == 2);
  // The designed input is worth more than the paper's sine: a smaller
  // Cramér–Rao bound on the same 200 samples.
  CHECK(cases[0]["parameters"][0]["cramer_rao"].get<double>() <
        cases[1]["parameters"][0]["cramer_rao"].get<double>());
  for (const auto& c : cases) {
    CHECK(c["runs"] == 4);
    const auto& p = c["parameters"][0];
    CHECK(std::abs(p["mean"].get<double>() - 1.0) < 4 * p["cramer_rao"].get<double>());
  }
}

TEST_CASE("studies: unknown or ill-typed options are errors") {
  const fs::path dir = scratch("study_bad");
  const std::string mop = quoted(std::string(MO_TEST_DATA_DIR) + "/DoubleIntegrator.mop");
  Run r = morun(mop + " -o " + quoted((dir / "a").string()) + " --option n_ee=3", dir);
  CHECK(r.status == 2);
  CHECK_THAT(r.err, Catch::Contains("unknown study option 'n_ee'"));
  r = morun(mop + " -o " + quoted((dir / "b").string()) + " --option n_cp=two", dir);
  CHECK(r.status == 2);
  CHECK_THAT(r.err, Catch::Contains("study option 'n_cp' expects an integer"));
  r = morun(quoted(std::string(MO_TEST_DATA_DIR) + "/BadOption.mop") + " -o " +
                quoted((dir / "c").string()),
            dir);
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Catch::Contains("BadOption.mop:11:24: error: study option 'criterion' expects one of"));
}

TEST_CASE("studies: Ipopt's second-order derivative checker finds no errors in the generated NLPs") {
  const fs::path dir = scratch("study_derivative_check");
  const std::string check = " --option hessian=exact --option " +
                            quoted("ipopt_options={\"derivative_test=second-order\"}") +
                            " --option max_iter=3";
  // Optimal control on a .mop and estimation on the cart-pendulum (exact Hessians).
  Run r = morun(quoted(std::string(MO_TEST_DATA_DIR) + "/DoubleIntegrator.mop") + " -o " +
                    quoted((dir / "mop").string()) + check + " --option n_e=8",
                dir);
  INFO(r.err);
  const std::string mop_log = slurp(dir / "mop" / "ipopt.log");
  CHECK_THAT(mop_log, Catch::Contains("No errors detected by derivative checker"));

  const fs::path data = dir / "data";
  // Small NLPs: the second-order checker differences every gradient entry
  // (slow under AddressSanitizer).
  r = morun(kOde + " -c CartPendulumODE --stop-time 2 --intervals 16 --measure y_x,y_phi --noise 0.01 "
                   "--input F=sine:3,1 -o " + quoted(data.string()),
            dir);
  REQUIRE(r.status == 0);
  r = morun(quoted(kCart + "CartPendulumEstimate.opt") + " -L " + kOde + " -o " +
                quoted((dir / "est").string()) + check + " --option n_e=6 --option " +
                quoted("data={\"" + (data / "measurements.csv").string() + "\"}") +
                " --option " + quoted("inputs={\"F=sine:3,1\"}"),
            dir);
  INFO(r.err);
  // The second-order check (Hessian against differences of the gradient and
  // constraint Jacobian) must be clean.
  const std::string log = slurp(dir / "est" / "ipopt.log");
  const auto second = log.find("Starting derivative checker for second derivatives.");
  REQUIRE(second != std::string::npos);
  const std::string hessian_part = log.substr(second, log.find("Number of nonzeros", second) - second);
  INFO(hessian_part);
  CHECK(hessian_part.find("\n* ") == std::string::npos);

  // The first-order check of the least-squares objective at Ipopt's default
  // perturbation (1e-8) flags a few gradient entries of ~1e3 at 1e-4..1e-3
  // relative: rounding in the forward difference of an objective of ~600.
  // At 1e-10 it flags dozens, at 1e-6 none: the gradient is right, and it is
  // checked at the perturbation where the difference is accurate.
  r = morun(quoted(kCart + "CartPendulumEstimate.opt") + " -L " + kOde + " -o " +
                quoted((dir / "est1").string()) + " --option max_iter=1 --option n_e=20 --option " +
                quoted("ipopt_options={\"derivative_test=first-order\", \"derivative_test_perturbation=1e-6\"}") +
                " --option " + quoted("data={\"" + (data / "measurements.csv").string() + "\"}") +
                " --option " + quoted("inputs={\"F=sine:3,1\"}"),
            dir);
  INFO(r.err);
  CHECK_THAT(slurp(dir / "est1" / "ipopt.log"), Catch::Contains("No errors detected by derivative checker"));
}
