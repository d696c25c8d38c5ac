// Sensitivities that stay true through events (issue 15): a bouncing ball
// (reinit), a time event whose time is a parameter with several clauses and
// an event iteration at one instant, a diode-like if-expression (the
// right-hand side jumps, no reinit), a discrete mode read by an if-expression,
// stick-slip friction and a switch inside a torn nonlinear block; discrete
// values held from the states (discrete sensitivities, our own model and the
// MSL's ZeroOrderHold) and indicators that read inputs. Each: generated
// sensitivity states and CVODES' module (rtol 1e-10) vs central differences
// of simulations (rtol 1e-12, step 1e-4 relative), at output times more than
// 1e-3 from an event.
#include <memory>

#include "e2e/cli.hpp"
#include "e2e/event_sensitivity_check.hpp"
#include "mo/runtime/input.hpp"

using namespace mo;
using namespace mo::e2e;

namespace {

tools::ModelSource data_model(const std::string& name) {
  return {kData + name + ".mo", name, {}, true};
}

/// Runs the three ways and checks both sensitivity kinds against the differences.
EventSensitivityRun check(const std::string& id, const std::string& model,
                          const std::vector<std::string>& parameters, const runtime::OutputGrid& grid,
                          double tolerance) {
  const auto run = run_through_events(id, data_model(model), parameters, grid, 1e-10, 1e-4);
  const double generated = worst_relative(run, run.generated, 1e-3, 1e-6);
  const double cvodes = worst_relative(run, run.cvodes, 1e-3, 1e-6);
  WARN(model << ": " << run.restarts << " crossings; sensitivities vs central differences, "
             << "worst relative difference: generated " << generated << ", CVODES " << cvodes);
  CHECK(run.restarts > 0);
  CHECK(generated < tolerance);
  CHECK(cvodes < tolerance);
  return run;
}

}  // namespace

TEST_CASE("bouncing ball: sensitivities jump at the bounce as finite differences do", "[events][sensitivities]") {
  const auto grid = runtime::OutputGrid::uniform(0, 1, 20);
  const auto run = check("e2e_ev_ball", "BouncingBall", {"g", "e", "h0"}, grid, 1e-5);
  // The issue's table: d(h)/d(g) at t = 0.5 and d(h)/d(e) at t = 0.8.
  CHECK(run.generated[10](0, 0) == Approx(0.0782).margin(5e-4));
  CHECK(run.generated[16](0, 1) == Approx(1.544).margin(1e-3));
  CHECK(run.generated[10](0, 0) == Approx(run.differences[10](0, 0)).margin(1e-5));
  CHECK(run.generated[16](0, 1) == Approx(run.differences[16](0, 1)).margin(1e-5));
}

TEST_CASE("a time event at a parameter time, two clauses and an event iteration at one instant",
          "[events][sensitivities]") {
  check("e2e_ev_kick", "TimedKick", {"T", "J", "dx", "k"}, runtime::OutputGrid::uniform(0, 2, 40), 1e-5);
}

TEST_CASE("a diode-like if-expression: the right-hand side jumps", "[events][sensitivities]") {
  check("e2e_ev_diode", "DiodeRC", {"Vf", "Roff", "A", "C"}, runtime::OutputGrid::uniform(0, 3, 60), 1e-4);
}

TEST_CASE("a discrete mode set by a when-clause and read by an if-expression", "[events][sensitivities]") {
  check("e2e_ev_mode", "FrictionMode", {"xb", "Fb", "k", "vs"}, runtime::OutputGrid::uniform(0, 4, 40), 1e-5);
}

TEST_CASE("stick-slip friction: mode, reinit and a force step at a parameter time",
          "[events][sensitivities]") {
  check("e2e_ev_stickslip", "StickSlip", {"k", "Fc", "tF", "F1"}, runtime::OutputGrid::uniform(0, 10, 100), 1e-4);
}

TEST_CASE("a switch inside a torn nonlinear block: the jump goes through Newton", "[events][sensitivities]") {
  // The relation v/(n*vt) > Maxexp reads unknowns of the block; f⁻ and f⁺ are
  // solved by the event right-hand side's own Newton block (which had no
  // scales and bounds, read past empty arrays and did not converge: the jump
  // was not finite), the indicator's tangent by the block's implicit-function
  // derivative. Tolerance: the difference quotient for G (step 5e-6) has a
  // noise of about 1e-4 of its largest value.
  check("e2e_ev_limit", "DiodeLimitLoop", {"R", "Maxexp", "n", "G"}, runtime::OutputGrid::uniform(0, 2, 40), 5e-4);
}

TEST_CASE("a sample-and-hold and a latched force: discrete sensitivities", "[events][sensitivities]") {
  // u = k (r - x) held at initial() and at every tick, F = c x + pre(F) + v + 0.1 t
  // latched at x > xs: S_u and S_F jump with the tangent of their values
  // (with dτ/dp of the crossing for F) and feed der(S_x) between events.
  // The value held from initial() stands until the first tick at 0.2; the grid
  // avoids the ticks at 0.2 + 0.1 k. CVODES' sensitivities
  // (f_x s + f_p) have no term for S_u and S_F: that run is refused.
  const auto run = run_through_events("e2e_ev_sampled", data_model("SampledControl"),
                                      {"k", "a", "xs", "x0", "c"}, runtime::OutputGrid::uniform(0, 2, 37),
                                      1e-10, 1e-4, false);
  // xs and c act on v alone, so d(x)/d(xs) and d(x)/d(c) are exactly 0: the
  // floor 1e-4 keeps the quotient's noise there (about 1e-7) out of the ratio.
  const double generated = worst_relative(run, run.generated, 1e-3, 1e-4);
  WARN("SampledControl: sensitivities vs central differences, worst relative difference " << generated);
  CHECK(run.event_times.size() > 15);
  CHECK(generated < 2e-3);
}

TEST_CASE("the MSL's ZeroOrderHold in a sampled loop: discrete sensitivities", "[events][sensitivities][msl]") {
  // The hold's `y = pre(ySample)` reads the held value through pre(): the
  // sensitivity equations read d(hold.ySample)/d(p) for it. The first tick is
  // at 0.2, so the hold on initial() stands until then.
  const std::string shared = shared_third_party_dir();
  if (shared.empty()) {
    WARN("SKIPPED: no ../shared/third_party (set MO_SHARED_DIR)");
    return;
  }
  const ModelicaPath msl(shared + "/third_party/msl-3.2.2");
  const auto run = run_through_events("e2e_ev_msl_hold", data_model("MslSampledLoop"),
                                      {"k", "plant.T", "plant.k", "plant.y_start"},
                                      runtime::OutputGrid::uniform(0, 2, 37), 1e-10, 1e-4, false);
  const double generated = worst_relative(run, run.generated, 1e-3, 1e-6);
  WARN("MslSampledLoop: sensitivities vs central differences, worst relative difference " << generated);
  CHECK(run.event_times.size() > 15);
  CHECK(generated < 1e-4);
}

TEST_CASE("indicators that read inputs: the event time moves with the inputs' slopes", "[events][sensitivities]") {
  // w from a table (linear between rows), v a sine: at each crossing of
  // x > w and x > w + v, dτ/dp = −(g_x S⁻ + g_p) / (g_x f⁻ + g_u u̇ + g_t).
  // Without the g_u u̇ term the jumps are wrong by the slopes' share.
  auto inputs = [] {
    auto table = std::make_shared<runtime::InputTable>(
        runtime::InputTable{{"w"}, {0, 1, 2, 4}, {{0.3, 0.9, 0.4, 1.0}}});
    runtime::Inputs u;
    u.add(runtime::table_input(table, "w"));
    u.add(runtime::sine_input(0.1, 0.5, 0.0, 0.1));
    return u;
  };
  const auto run = run_through_events("e2e_ev_inputs", data_model("InputCrossing"), {"a", "b", "k", "c"},
                                      runtime::OutputGrid::uniform(0, 4, 80), 1e-10, 1e-4, true, inputs);
  // k and c act on y alone, so d(x)/d(k) and d(x)/d(c) are exactly 0: the
  // floor 1e-4 keeps the quotient's noise there (4e-9) out of the ratio.
  const double generated = worst_relative(run, run.generated, 1e-3, 1e-4);
  const double cvodes = worst_relative(run, run.cvodes, 1e-3, 1e-4);
  WARN("InputCrossing: " << run.restarts << " crossings; worst relative difference: generated "
                         << generated << ", CVODES " << cvodes);
  CHECK(run.restarts >= 3);
  CHECK(generated < 1e-4);
  CHECK(cvodes < 1e-4);
}

TEST_CASE("two balls bounce at one instant: two indicators cross together", "[events][sensitivities]") {
  // g and h0 move both bounces together (one dτ/dp for both indicators);
  // e1 and e2 act only in their own reinit, so d(ball 2)/d(e1) is exactly 0:
  // the floor 1e-4 keeps the quotient's noise there (5e-11) out of the ratio.
  const auto run = run_through_events("e2e_ev_two_balls", {kData + "TwoBalls.mop", "TwoBallsModel", {}, true},
                                      {"g", "h0", "e1", "e2"}, runtime::OutputGrid::uniform(0, 1, 20), 1e-10, 1e-4);
  CHECK(run.event_times.size() == 2);  // both balls at 0.45, ball 2 alone at 0.99
  CHECK(worst_relative(run, run.generated, 1e-3, 1e-4) < 1e-5);
  CHECK(worst_relative(run, run.cvodes, 1e-3, 1e-4) < 1e-5);
}

TEST_CASE("a design on a model with events it cannot take (Zeno) is refused at the when-clause, never 'success'",
          "[events][studies]") {
  const fs::path dir = scratch("study_events");
  const Run r = morun(quoted(kData + "BallZeno.mop") + " -o " + quoted((dir / "out").string()) +
                          " --option task=design --option parameters={g} --option outputs={h} --option sigma={0.01}",
                      dir);
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.find("BallZeno.mop:12:3: error:") != std::string::npos);
  CHECK(r.err.find("chattering or Zeno") != std::string::npos);
  CHECK(!fs::exists(dir / "out" / "summary.json"));
}
