// Input design on small models: the Fisher information of the collocation
// solution against its replay on CVODES, and problem checks.
#include "fixtures.hpp"
#include "mo/runtime/design.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace mo::runtime;

namespace {


// a' = -k a + u, b' = a on [0, 2] with |u| <= 1, measuring a and k·b, for (k, a0).
InputDesignProblem decay_design(DesignCriterion criterion) {
  InputDesignProblem d;
  d.ocp.t0 = 0.0, d.ocp.tf = 2.0;
  d.ocp.controls = {FreeControl{0, {-1.0, 1.0}, sine_input(0.5, 0.5), {}}};
  d.ocp.collocation.n_e = 20, d.ocp.collocation.n_cp = 3;
  d.ocp.solver.acceptable_tolerance = 1e-2;
  d.ocp.solver.acceptable_objective_change = 1e-6;
  d.parameters = {0, 1};
  d.measurements = {{0, 1}, {0.1, 0.1}, MeasurementDesign::uniform_times(0.0, 2.0, 20)};
  d.criterion = criterion;
  return d;
}

}  // namespace

TEST_CASE("input design: the collocation Fisher matrix matches its CVODES replay", "[design]") {
  fixtures::WithSensitivities<fixtures::LinearDecay> model;
  for (DesignCriterion c : {DesignCriterion::T, DesignCriterion::D, DesignCriterion::A,
                            DesignCriterion::E}) {
    CAPTURE(int(c));
    InputDesignResult r = design_input(model, decay_design(c));
    INFO(r.optimization.message);
    REQUIRE(r.optimization.ok());
    REQUIRE(r.fisher_resimulated.rows() == 2);
    CHECK((r.fisher_collocation - r.fisher_resimulated).norm() <
          1e-3 * r.fisher_resimulated.norm());
    CHECK(r.information_collocation == Approx(criterion_information(c, r.fisher_collocation)));
    for (double u : r.optimization.control_values[0]) CHECK(std::abs(u) <= 1.0 + 1e-6);
  }
}

TEST_CASE("input design: each criterion beats the others on its own measure", "[design]") {
  fixtures::WithSensitivities<fixtures::LinearDecay> model;
  std::vector<Eigen::MatrixXd> fisher;
  const std::vector<DesignCriterion> criteria{DesignCriterion::T, DesignCriterion::D,
                                              DesignCriterion::E};
  for (DesignCriterion c : criteria) {
    InputDesignResult r = design_input(model, decay_design(c));
    REQUIRE(r.optimization.ok());
    fisher.push_back(r.fisher_collocation);
  }
  for (std::size_t i = 0; i < criteria.size(); ++i)
    for (std::size_t j = 0; j < criteria.size(); ++j)
      CHECK(criterion_information(criteria[i], fisher[i]) >=
            criterion_information(criteria[i], fisher[j]) - 1e-6 * std::abs(criterion_information(criteria[i], fisher[i])));
}

TEST_CASE("input design: several starts keep the best", "[design]") {
  fixtures::WithSensitivities<fixtures::LinearDecay> model;
  InputDesignProblem d = decay_design(DesignCriterion::D);
  d.starts = {std::shared_ptr<const InputSignal>(constant_input(0.5)), sine_input(1.0, 1.0)};
  InputDesignResult r = design_input(model, d);
  INFO(r.optimization.message);
  REQUIRE(r.optimization.ok());
  REQUIRE(r.start_information.size() == 2);
  for (double reached : r.start_information)
    if (!std::isnan(reached)) CHECK(r.information_collocation >= reached);
}

TEST_CASE("input design rejects a model without the sensitivity states", "[design]") {
  fixtures::LinearDecay plant;  // no sensitivity states
  InputDesignResult r = design_input(plant, decay_design(DesignCriterion::T));
  CHECK(r.optimization.status == OptimizationStatus::invalid_problem);
  CHECK(r.optimization.message.find("no sensitivity states for parameter k") != std::string::npos);
}
