// Sensitivities through events against central differences of whole
// simulations: the generated sensitivity states and CVODES' module (both with
// the jump conditions of docs/events.md) vs (x(p + h) - x(p - h)) / 2h.
#pragma once

#include <functional>

#include "e2e/support.hpp"
#include "mo/runtime/simulate.hpp"

namespace mo::e2e {

/// The three sensitivity matrices (base states × parameters) per grid time.
struct EventSensitivityRun {
  std::vector<Eigen::MatrixXd> generated, cvodes, differences;
  std::vector<double> times;        ///< the grid
  std::vector<double> event_times;  ///< of the nominal run (events that changed something)
  long restarts = 0;                ///< integrator restarts: every crossing, changing or not
};

inline runtime::SimulationOptions event_options(runtime::SensitivityMethod method,
                                                std::vector<std::size_t> parameters, double rtol) {
  runtime::SimulationOptions o;
  o.relative_tolerance = rtol;
  o.absolute_tolerance = rtol * 1e-2;
  o.sensitivities.method = method;
  o.sensitivities.parameters = std::move(parameters);
  return o;
}

/// Runs the three ways; REQUIREs that every simulation succeeds. `step` is the
/// relative difference step (times max(1e-3, |p|)). Without `cvodes_carries`
/// (a discrete variable moves with the parameters: only the generated
/// sensitivity states carry it), REQUIREs that CVODES' run is refused so.
/// `inputs` makes the model's input signals for each run (none if empty).
inline EventSensitivityRun run_through_events(const std::string& id, const tools::ModelSource& source,
                                              const std::vector<std::string>& parameters,
                                              const runtime::OutputGrid& grid, double rtol,
                                              double step, bool cvodes_carries = true,
                                              const std::function<runtime::Inputs()>& inputs = {}) {
  auto signals = [&] { return inputs ? inputs() : runtime::Inputs(); };
  auto plain = compiled_model(id, {source, {}});
  auto augmented = compiled_model(id + "_sens", {source, parameters});
  const auto& info = plain->info();
  const std::size_t nb = info.states.size();
  REQUIRE(augmented->info().num_base_states() == nb);
  std::vector<std::size_t> J, J_augmented;
  for (const auto& name : parameters) {
    J.push_back(parameter(info, name));
    J_augmented.push_back(parameter(augmented->info(), name));
  }
  const auto p = info.default_parameters();
  EventSensitivityRun out;
  out.times = grid.times;
  const auto generated = runtime::simulate(*augmented, signals(), augmented->info().default_parameters(), grid,
                                           event_options(runtime::SensitivityMethod::model_states, J_augmented, rtol));
  INFO(generated.message);
  REQUIRE(generated.ok());
  out.generated = generated.state_sensitivities;
  out.event_times = generated.event_times;
  out.restarts = generated.statistics.restarts;
  const auto cvodes = runtime::simulate(*plain, signals(), p, grid,
                                        event_options(runtime::SensitivityMethod::cvodes_analytic, J, rtol));
  INFO(cvodes.message);
  if (cvodes_carries) {
    REQUIRE(cvodes.ok());
    out.cvodes = cvodes.state_sensitivities;
  } else {
    REQUIRE(cvodes.status == runtime::SimulationStatus::invalid_problem);
    REQUIRE_THAT(cvodes.message, Catch::Contains("not by CVODES"));
  }
  out.differences.assign(grid.times.size(), Eigen::MatrixXd(static_cast<Eigen::Index>(nb),
                                                            static_cast<Eigen::Index>(J.size())));
  // References two orders tighter: the difference quotient divides their error by the step.
  const auto reference = event_options(runtime::SensitivityMethod::none, {}, rtol * 1e-2);
  for (std::size_t j = 0; j < J.size(); ++j) {
    auto q = p;
    const double h = step * std::max(1e-3, std::fabs(p[J[j]]));
    q[J[j]] = p[J[j]] + h;
    const auto plus = runtime::simulate(*plain, signals(), q, grid, reference);
    q[J[j]] = p[J[j]] - h;
    const auto minus = runtime::simulate(*plain, signals(), q, grid, reference);
    INFO(plus.message << minus.message);
    REQUIRE(plus.ok());
    REQUIRE(minus.ok());
    for (std::size_t k = 0; k < grid.times.size(); ++k)
      for (std::size_t i = 0; i < nb; ++i)
        out.differences[k](static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
            (plus.trajectory.at(k, i) - minus.trajectory.at(k, i)) / (2 * h);
  }
  return out;
}

/// max over grid times at least `margin` away from every event of
/// |a - b| / (max over time of |b(i, j)| + floor), per entry.
inline double worst_relative(const EventSensitivityRun& run, const std::vector<Eigen::MatrixXd>& a,
                             double margin, double floor) {
  const auto& b = run.differences;
  REQUIRE(a.size() == b.size());
  Eigen::MatrixXd scale = Eigen::MatrixXd::Constant(b.front().rows(), b.front().cols(), floor);
  for (const auto& m : b) scale = scale.cwiseMax(m.cwiseAbs() + Eigen::MatrixXd::Constant(m.rows(), m.cols(), floor));
  double worst = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const double t = run.times[k];
    const bool near = std::any_of(run.event_times.begin(), run.event_times.end(),
                                  [&](double te) { return std::fabs(te - t) < margin; });
    if (near) continue;
    REQUIRE(a[k].rows() == b[k].rows());
    REQUIRE(a[k].cols() == b[k].cols());
    worst = std::max(worst, ((a[k] - b[k]).cwiseAbs().array() / scale.array()).maxCoeff());
  }
  return worst;
}

}  // namespace mo::e2e
