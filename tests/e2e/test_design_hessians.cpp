// Input design with the Fisher matrix lifted into the NLP (issue 11.1): every
// criterion's exact Hessian against Ipopt's finite-difference derivative
// checker, and the A/T/D/E designs of a two-parameter first-order plant
// converging in tens of iterations with the collocation F matching its CVODES
// replay.
#include <nlohmann/json.hpp>

#include "e2e/cli.hpp"
#include "e2e/support.hpp"

using namespace mo::e2e;
using nlohmann::json;

namespace {

const std::string kFirstOrder = quoted(std::string(MO_TEST_DATA_DIR) + "/FirstOrderDesign.mop");

/// The text of Ipopt's log between the start of the `which` check and its summary.
std::string checker_section(const std::string& log, const std::string& which) {
  const auto at = log.find("Starting derivative checker for " + which + " derivatives.");
  if (at == std::string::npos) return "(no " + which + "-derivative check in the log)\n* ";
  return log.substr(at, log.find("Number of nonzeros", at) - at);
}

/// Ipopt's first- and second-order derivative checks in `log_file` ran and
/// starred no entry.
void check_derivatives(const fs::path& log_file) {
  const std::string log = slurp(log_file);
  REQUIRE(log.find("Starting derivative checker") != std::string::npos);
  const std::string first = checker_section(log, "first");
  const std::string second = checker_section(log, "second");
  INFO(first);
  INFO(second);
  CHECK(first.find("\n* ") == std::string::npos);
  CHECK(second.find("\n* ") == std::string::npos);
}

}  // namespace

TEST_CASE("design: the lifted Fisher NLP's exact Hessian passes Ipopt's derivative checker",
          "[design_hessians]") {
  for (const std::string criterion : {"A", "T", "D", "E"}) {
    CAPTURE(criterion);
    const fs::path dir = scratch("design_hessian_check_" + criterion);
    // z = decay·x² is measured too: its sensitivity outputs have second derivatives.
    const Run r = morun(kFirstOrder + " -o " + quoted((dir / "out").string()) +
                            " --option criterion=" + criterion +
                            " --option hessian=exact --option hessian_fallback=false"
                            " --option max_iter=2 --option n_e=8"
                            " --option measurements=8 --option 'outputs={y, z}'"
                            " --option 'sigma={0.01, 0.1}' --option "
                            "'ipopt_options={\"derivative_test=second-order\", "
                            "\"derivative_test_perturbation=1e-7\"}'",
                        dir);
    INFO(r.err);
    check_derivatives(dir / "out" / "ipopt.log");
  }
}

TEST_CASE("design: A, T, D and E designs of a first-order plant converge with exact Hessians",
          "[design_hessians]") {
  for (const std::string criterion : {"A", "T", "D", "E"}) {
    CAPTURE(criterion);
    const fs::path dir = scratch("design_exact_" + criterion);
    const Run r = morun(kFirstOrder + " -o " + quoted((dir / "out").string()) +
                            " --option criterion=" + criterion,
                        dir);
    INFO(r.err);
    REQUIRE(r.status == 0);
    const json s = json::parse(slurp(dir / "out" / "summary.json"));
    CHECK(s["status"] == "success");
    CHECK(s["nlp"]["hessian_nonzeros"].get<int>() > 0);
    CHECK(s["iterations"].get<int>() <= 60);
    const double coll = s["design"]["information_collocation"].get<double>();
    const double resim = s["design"]["information_resimulated"].get<double>();
    CHECK(std::abs(coll - resim) <= 1e-3 * std::abs(resim));
  }
}

TEST_CASE("design: init_traj and nominal_traj can be switched off", "[design_hessians]") {
  const fs::path dir = scratch("design_no_init_traj");
  // Unscaled states still converge to the same D optimum (27.40).
  Run r = morun(kFirstOrder + " -o " + quoted((dir / "unscaled").string()) +
                    " --option criterion=D --option nominal_traj=false",
                dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  json s = json::parse(slurp(dir / "unscaled" / "summary.json"));
  CHECK(s["status"] == "success");
  const double scaled_optimum = 27.4044;  // with init_traj and nominal_traj (the defaults)
  CHECK(s["design"]["information_resimulated"].get<double>() == Approx(scaled_optimum).epsilon(1e-4));
  // Without init_traj the states start at x = 0 while the input guess is 0.5:
  // the collocation rows are violated at the start. (This start leads to a
  // flat region where the D design crawls: the simulation start matters.)
  r = morun(kFirstOrder + " -o " + quoted((dir / "cold").string()) +
                " --option criterion=D --option init_traj=false --option max_iter=30",
            dir);
  INFO(r.err);
  s = json::parse(slurp(dir / "cold" / "summary.json"));
  CHECK(s["iterations"].get<int>() > 0);
  CHECK(s["design"]["information_resimulated"].get<double>() <= scaled_optimum + 1e-3);
}

TEST_CASE("design: Ipopt runs without MUMPS's scaling unless ipopt_options asks for it",
          "[design_hessians]") {
  // MUMPS's matching-based scaling misjudges the inertia of design KKT
  // matrices (docs/design-formulation.md, "Linear algebra").
  for (const std::string scaling : {"", "77"}) {
    CAPTURE(scaling);
    const fs::path dir = scratch("design_mumps_scaling" + scaling);
    std::string options = "\"print_user_options=yes\"";
    if (!scaling.empty()) options += ", \"mumps_scaling=" + scaling + "\"";
    const Run r = morun(kFirstOrder + " -o " + quoted((dir / "out").string()) +
                            " --option criterion=D --option 'ipopt_options={" + options + "}'",
                        dir);
    INFO(r.err);
    REQUIRE(r.status == 0);
    const std::string log = slurp(dir / "out" / "ipopt.log");
    const std::string expected = scaling.empty() ? "0" : scaling;
    CHECK(log.find("mumps_scaling = " + expected) != std::string::npos);
    const json s = json::parse(slurp(dir / "out" / "summary.json"));
    CHECK(s["status"] == "success");
    CHECK(s["design"]["information_resimulated"].get<double>() == Approx(27.4044).epsilon(1e-4));
  }
}

TEST_CASE("design: a multi-phase design's exact Hessian passes Ipopt's derivative checker",
          "[design_hessians][events]") {
  // One point carries every sample of every phase as an output, each with its
  // own phase's columns (design_fisher_samples.hpp): 4 phases, 2 parameters.
  const fs::path dir = scratch("design_hessian_check_phases");
  const Run r = morun(quoted(std::string(MO_TEST_DATA_DIR) + "/SampledDesign.mop") + " -o " +
                          quoted((dir / "out").string()) +
                          " --set T=0.5 --option criterion=D --option measurements=4 --option n_e=8"
                          " --option max_iter=1 --option hessian_fallback=false --option "
                          "'ipopt_options={\"derivative_test=second-order\", "
                          "\"derivative_test_perturbation=1e-7\"}'",
                      dir);
  INFO(r.err);
  check_derivatives(dir / "out" / "ipopt.log");
}

TEST_CASE("design: a multi-phase design that ends at the iteration limit tries the limited-memory fallback",
          "[design_hessians][events]") {
  // The stacked model has its phases' sensitivities as outputs only: the
  // fallback takes the lifted F with L-BFGS (it used to refuse, and the
  // study then crashed on the empty result).
  const fs::path dir = scratch("design_phases_fallback");
  const Run r = morun(quoted(std::string(MO_TEST_DATA_DIR) + "/SampledDesign.mop") + " -o " +
                          quoted((dir / "out").string()) + " --option max_iter=1",
                      dir);
  INFO(r.err);
  CHECK(r.status == 1);
  const json s = json::parse(slurp(dir / "out" / "summary.json"));
  CHECK(s["status"] == "iteration_limit");
  const json& attempts = s["design"]["attempts"];
  REQUIRE(attempts.size() == 2);
  CHECK(attempts[0]["hessian"] == "exact");
  CHECK(attempts[1]["hessian"] == "limited_memory");
  CHECK(attempts[1]["status"] == "iteration_limit");
  CHECK(fs::exists(dir / "out" / "designed_input.csv"));
  CHECK(fs::exists(dir / "out" / "ipopt_limited_memory.log"));
}

TEST_CASE("design: ipopt_options are set by the type Ipopt registered and refused when Ipopt refuses them",
          "[design_hessians]") {
  struct Case {
    std::string options, message;  // message empty: accepted
  };
  const std::vector<Case> cases{
      {R"("bound_push=1", "print_user_options=yes")", ""},  // a number written as an integer
      {R"("mu_stratgy=adaptive")", "ipopt_options: 'mu_stratgy' is not an option of Ipopt"},
      {R"("mu_strategy=bogus")", "ipopt_options: 'bogus' is not a valid value of Ipopt's option 'mu_strategy'"},
      {R"("max_iter=1e3")", "ipopt_options: '1e3' is not a valid value of Ipopt's option 'max_iter' (an integer"},
  };
  int k = 0;
  for (const Case& c : cases) {
    CAPTURE(c.options);
    const fs::path dir = scratch("design_ipopt_options" + std::to_string(k++));
    const Run r = morun(kFirstOrder + " -o " + quoted((dir / "out").string()) + " --option 'ipopt_options={" +
                            c.options + "}'",
                        dir);
    INFO(r.err);
    const json s = json::parse(slurp(dir / "out" / "summary.json"));
    if (c.message.empty()) {
      CHECK(r.status == 0);
      CHECK(slurp(dir / "out" / "ipopt.log").find("bound_push = 1") != std::string::npos);
    } else {
      CHECK(r.status != 0);
      CHECK(s["status"] == "invalid_problem");
      CHECK(s["message"].get<std::string>().find(c.message) != std::string::npos);
      CHECK(r.err.find(c.message) != std::string::npos);
    }
  }
}
