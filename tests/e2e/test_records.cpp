// Records through functions, equations and bindings (tests/e2e/data/Records.mo),
// simulated against closed forms: a record state through a function with a
// record parameter (the oscillator, its sensitivity to a record field), and
// record constructors, nested records, array fields, arrays of records and
// a record chosen by a varying condition (Geometry).
#include <cmath>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

tools::ModelSource records(const std::string& cls) { return {kData + "Records.mo", cls, {}, true}; }

}  // namespace

TEST_CASE("records: a record state through a function of records, and its sensitivity to a record field",
          "[e2e][records]") {
  auto model = compiled_model("e2e_records_oscillator", {records("Records.Oscillator"), {"sp.k"}});
  const auto& info = model->info();
  const auto grid = runtime::OutputGrid::uniform(0, 3, 60);
  runtime::SimulationOptions o = tight();
  o.sensitivities.method = runtime::SensitivityMethod::model_states;
  const auto r = runtime::simulate(*model, {}, info.default_parameters(), grid, o);
  INFO(r.message);
  REQUIRE(r.ok());
  const auto x = column(r.trajectory, "s.x");
  const auto dx_dk = column(r.trajectory, "d(s.x)/d(sp.k)");
  // k = 4, m = 1, c = 0: x = cos(2 t), dx/dk = -sin(2 t) t / (2 sqrt(k m)) = -t sin(2 t) / 4.
  for (std::size_t i = 0; i < grid.times.size(); ++i) {
    const double t = grid.times[i];
    INFO("t = " << t);
    CHECK(x[i] == Approx(std::cos(2 * t)).margin(1e-6));
    CHECK(dx_dk[i] == Approx(-t * std::sin(2 * t) / 4).margin(1e-6));
  }
}

TEST_CASE("records: constructors, nested records, array fields, arrays of records, a varying choice",
          "[e2e][records]") {
  auto model = compiled_model("e2e_records_geometry", {records("Records.Geometry"), {}});
  const auto grid = runtime::OutputGrid::uniform(0, 2, 40);  // t = 1 (a tie) is a grid point
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const std::string names[] = {"w.x", "w.y", "v.x", "v.y", "n", "L", "area"};  // y[1] .. y[7]
  std::vector<std::vector<double>> values;
  for (std::size_t k = 0; k < std::size(names); ++k)
    values.push_back(variable("e2e_records_geometry", r.trajectory, model->info().default_parameters(),
                              "y[" + std::to_string(k + 1) + "]"));
  for (std::size_t i = 0; i < grid.times.size(); ++i) {
    const double t = grid.times[i];
    INFO("t = " << t);
    // c = (3, 4), w = flip((2, t), 3) = (3 t, 6); the rightmost of c, w and
    // (2 + t, 1) is c before t = 1 and w after (all three tie at t = 1).
    const bool after = t > 1;
    const double expected[] = {3 * t, 6, after ? 3 * t : 3, after ? 6.0 : 4.0,
                               std::hypot(3 * t - 3, 2.0), 15, 4};
    for (std::size_t k = 0; k < std::size(names); ++k) {
      INFO(names[k]);
      CHECK(values[k][i] == Approx(expected[k]).margin(1e-9));
    }
  }
}
