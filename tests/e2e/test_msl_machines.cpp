// The MSL's Electrical.Machines (tests/e2e/data/MslMachines.mo): the direct-on-line
// start of an induction machine settles at the nominal speed its example was
// built for. The machine's model exercises multi-phase plugs (whose phase
// count m is a connected parameter), arrays of components with switched-off
// conditional heat ports, and Boolean constants passed on in modifiers.
#include <cmath>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

using namespace mo;
using namespace mo::e2e;

TEST_CASE("the MSL's AIMC_DOL starts and settles at the nominal speed", "[msl]") {
  // Found by Modelica's lookup on MODELICAPATH, as a user runs it.
  auto model = msl_compiled_model("e2e_msl_aimc_dol", {{kData + "MslMachines.mo", "AimcDol", {}, true}, {}});
  if (!model) return;
  const auto grid = runtime::OutputGrid::uniform(0, 1.5, 150);
  const auto r = runtime::simulate(*model, {}, model->info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto w = column(r.trajectory, "aimc.wMechanical");
  // At rest until the switch closes at 0.1 s.
  CHECK(std::fabs(w[5]) < 1e-9);
  // Settled at the load's nominal point, 1440.45 rpm (where the machine's
  // torque meets the quadratic load's 161.4 N.m).
  const double w_nominal = 1440.45 * 2 * M_PI / 60;
  CHECK(w.back() == Approx(w_nominal).epsilon(1e-4));
  CHECK(w[140] == Approx(w.back()).epsilon(1e-6));
  // Accelerating on the way: below half the nominal speed at 0.2 s.
  CHECK(w[20] > 0.0);
  CHECK(w[20] < 0.5 * w_nominal);
}
