// The limited-memory fallback of a failed exact-Hessian design (issue 11,
// docs/design-formulation.md "Fallback"): FirstOrderDesign's T design
// measuring z = decay·x² needs 14 exact-Hessian iterations and 9 L-BFGS ones,
// so with max_iter = 10 the exact solve stops at the iteration limit and the
// fallback from the same start converges.
#include <nlohmann/json.hpp>

#include "e2e/cli.hpp"
#include "e2e/support.hpp"

using namespace mo::e2e;
using nlohmann::json;

namespace {

const std::string kFirstOrder = quoted(std::string(MO_TEST_DATA_DIR) + "/FirstOrderDesign.mop");

/// The T design of z with `args`; its summary.json.
json fallback_design(const std::string& name, const std::string& args, int expected_status) {
  const fs::path dir = scratch(name);
  const Run r = morun(kFirstOrder + " -o " + quoted((dir / "out").string()) +
                          " --option criterion=T --option 'outputs={z}' " + args,
                      dir);
  INFO(r.err);
  REQUIRE(r.status == expected_status);
  return json::parse(slurp(dir / "out" / "summary.json"));
}

}  // namespace

TEST_CASE("design: an exact-Hessian design at its iteration limit is solved again with L-BFGS",
          "[design_fallback]") {
  const json s = fallback_design("design_fallback", "--option max_iter=10", 0);
  CHECK(s["status"] == "success");
  const json& a = s["design"]["attempts"];
  REQUIRE(a.size() == 2);
  CHECK(a[0]["hessian"] == "exact");
  CHECK(a[0]["status"] == "iteration_limit");
  CHECK(a[0]["iterations"] == 10);
  CHECK(a[0]["kept"] == false);
  CHECK(a[0]["kkt"]["primal_infeasibility"].get<double>() > 1e-6);  // stopped short
  CHECK(a[1]["hessian"] == "limited_memory");
  CHECK(a[1]["status"] == "success");
  CHECK(a[1]["kept"] == true);
  CHECK(a[1]["kkt"]["primal_infeasibility"].get<double>() < 1e-6);
  CHECK(a[1]["kkt"]["dual_infeasibility"].is_number());
  CHECK(a[1]["kkt"]["complementarity"].is_number());
  // The kept attempt is the result: its iterations, its information; both solves timed.
  CHECK(s["iterations"] == a[1]["iterations"]);
  CHECK(s["design"]["information_collocation"] == a[1]["information_collocation"]);
  CHECK(s["timings_seconds"]["ipopt"].get<double>() >=
        a[0]["solve_seconds"].get<double>() + a[1]["solve_seconds"].get<double>() - 1e-9);
  REQUIRE(s["retries"].size() == 1);
  CHECK(s["retries"][0].get<std::string>().find("kept the limited-memory design") != std::string::npos);
  // The same optimum as the exact Hessian reaches without the limit (1.46929e7).
  const json full = fallback_design("design_fallback_unlimited", "", 0);
  REQUIRE(full["design"]["attempts"].size() == 1);
  CHECK(full["design"]["attempts"][0]["hessian"] == "exact");
  CHECK(s["design"]["information_resimulated"].get<double>() ==
        Approx(full["design"]["information_resimulated"].get<double>()).epsilon(1e-5));
}

TEST_CASE("design: hessian_fallback = false keeps the failed exact-Hessian design",
          "[design_fallback]") {
  const json s = fallback_design("design_no_fallback", "--option max_iter=10 --option hessian_fallback=false", 1);
  CHECK(s["status"] == "iteration_limit");
  REQUIRE(s["design"]["attempts"].size() == 1);
  CHECK(s["design"]["attempts"][0]["kept"] == true);
  CHECK(s["retries"].empty());
}

TEST_CASE("design: when the fallback fails too, the exact-Hessian result is kept", "[design_fallback]") {
  // Five iterations are too few for either Hessian.
  const json s = fallback_design("design_fallback_both_fail", "--option max_iter=5", 1);
  CHECK(s["status"] == "iteration_limit");
  const json& a = s["design"]["attempts"];
  REQUIRE(a.size() == 2);
  CHECK(a[0]["kept"] == true);
  CHECK(a[1]["kept"] == false);
  CHECK(a[1]["status"] == "iteration_limit");
  CHECK(s["iterations"] == 5);
  CHECK(s["design"]["information_collocation"] == a[0]["information_collocation"]);
}

TEST_CASE("design: hessian = limited_memory runs once, without a fallback", "[design_fallback]") {
  const json s = fallback_design("design_lbfgs_once", "--option max_iter=5 --option hessian=limited_memory", 1);
  REQUIRE(s["design"]["attempts"].size() == 1);
  CHECK(s["design"]["attempts"][0]["hessian"] == "limited_memory");
}
