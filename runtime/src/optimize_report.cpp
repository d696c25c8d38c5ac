// Collecting an optimisation result: trajectories, controls, the re-simulation
// check, and the files trajectories.csv, resimulated.csv and summary.json.
#include "mo/runtime/optimize.hpp"

#include "mo/runtime/simulate.hpp"
#include "optimize_internal.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace mo::runtime {
namespace {

Inputs inputs_for(const std::map<std::size_t, std::shared_ptr<const InputSignal>>& fixed,
                  const std::vector<FreeControl>& controls, const OptimizationResult& result,
                  std::size_t num_inputs) {
  std::vector<std::unique_ptr<InputSignal>> signals(num_inputs);
  for (const auto& [input, signal] : fixed) signals[input] = shared_input(signal);
  std::vector<double> starts(result.element_times.begin(), result.element_times.end() - 1);
  for (std::size_t c = 0; c < controls.size(); ++c)
    signals[controls[c].input] =
        controls[c].per_point ? collocated_input(starts, result.element_times.back(), result.collocation_points,
                                                 result.control_values[c])
                              : piecewise_constant_input(starts, result.control_values[c]);
  return Inputs(std::move(signals));
}

std::vector<std::string> trajectory_names(const ModelInfo& info) {
  std::vector<std::string> names;
  for (const auto& s : info.states) names.push_back(s.name);
  for (const auto& u : info.inputs) names.push_back(u.name);
  return names;
}

// Largest excess of `value` over `b`, ≥ 0.
double excess(double value, Bounds b) { return std::max({0.0, b.lo - value, value - b.hi}); }

std::vector<Bounds> state_bounds(const ModelInfo& info, const detail::ExperimentSetup& s) {
  std::vector<Bounds> bounds;
  for (std::size_t k = 0; k < info.states.size(); ++k) {
    auto it = s.state_bounds.find(k);
    bounds.push_back(it != s.state_bounds.end() ? it->second
                                                : Bounds{info.states[k].min, info.states[k].max});
  }
  return bounds;
}

// Worst violation of state, final-state and path bounds along the simulated trajectory.
void measure_violation(const ModelInfo& info, const detail::ExperimentSetup& s,
                       const std::vector<PathConstraint>& path, const ResultTable& sim,
                       ResimulationCheck& check) {
  const std::vector<Bounds> bounds = state_bounds(info, s);
  const std::size_t nx = info.states.size();
  auto note = [&](double amount, const std::string& name, double t) {
    if (amount > check.max_bound_violation)
      check.max_bound_violation = amount, check.worst_bound = name, check.worst_bound_time = t;
  };
  for (std::size_t k = 0; k < sim.rows(); ++k) {
    for (std::size_t x = 0; x < nx; ++x)
      note(excess(sim.at(k, x), bounds[x]), info.states[x].name, sim.times()[k]);
    for (const PathConstraint& c : path)
      note(excess(sim.at(k, nx + c.output), c.bounds), info.outputs[c.output].name, sim.times()[k]);
  }
  if (sim.rows() == 0) return;
  const std::size_t last = sim.rows() - 1;
  for (const FinalStateConstraint& f : s.final_state)
    note(excess(sim.at(last, f.state), f.bounds), info.states[f.state].name + "(tf)",
         sim.times()[last]);
}

ResimulationCheck resimulate(detail::CollocationNlp& nlp, int e, const OptimizationResult& r,
                             const std::vector<PathConstraint>& path) {
  const ModelInfo& info = nlp.info();
  const detail::ExperimentSetup& s = nlp.experiment(e);
  ResimulationCheck check;
  Inputs inputs = inputs_for(s.fixed_inputs, s.controls, r, info.inputs.size());
  SimulationOptions options;
  options.relative_tolerance = 1e-10;
  options.absolute_tolerance = 1e-10;
  std::unique_ptr<Model> model = nlp.model(e).clone();
  SimulationResult sim =
      simulate(*model, inputs, r.parameters, OutputGrid::at(r.trajectories.times()), options);
  check.performed = sim.ok();
  check.message = sim.message;
  const std::size_t nx = info.states.size(), nu = info.inputs.size();
  check.resimulated = ResultTable(trajectory_names(info));
  std::vector<double> row(nx + nu);
  for (std::size_t k = 0; k < sim.trajectory.rows(); ++k) {
    const double t = sim.trajectory.times()[k];
    std::copy_n(sim.trajectory.row(k).begin(), nx, row.begin());
    inputs.evaluate(t, std::span<double>(row).subspan(nx));
    check.resimulated.add_row(t, row);
    for (std::size_t x = 0; x < nx; ++x) {
      double diff = std::abs(sim.trajectory.at(k, x) - r.trajectories.at(k, x));
      if (diff > check.max_state_difference)
        check.max_state_difference = diff, check.worst_state = info.states[x].name,
        check.worst_state_time = t;
    }
  }
  measure_violation(info, s, path, sim.trajectory, check);
  return check;
}

}  // namespace

namespace detail {

OptimizationResult collect_result(CollocationNlp& nlp, const IpoptOutcome& outcome, int e,
                                  const std::vector<PathConstraint>& path) {
  OptimizationResult r;
  r.status = outcome.status, r.message = outcome.message, r.retries = outcome.retries;
  r.objective = outcome.objective, r.iterations = outcome.iterations, r.size = outcome.size;
  r.kkt = outcome.kkt;
  r.timings.solve = outcome.solve_seconds;
  r.timings.function_evaluations = outcome.evaluation_seconds;
  const ModelInfo& info = nlp.info();
  const std::vector<double>& v = outcome.solution;
  r.parameters.resize(info.parameters.size());
  nlp.parameters(v, r.parameters);
  r.trajectories = ResultTable(trajectory_names(info));
  const std::size_t nx = info.states.size();
  std::vector<double> row(nx + info.inputs.size());
  auto add_node = [&](int i, int k, double tau) {  // i = n_e: b_{n_e} at the last element's end
    PointRef pt = nlp.point(e, std::min(i, nlp.num_elements() - 1), tau);
    for (std::size_t x = 0; x < nx; ++x) row[x] = v[std::size_t(nlp.state_var(e, i, k, int(x)))];
    nlp.point_inputs(v, pt, std::span<double>(row).subspan(nx));
    r.trajectories.add_row(pt.time, row);
  };
  const auto& tau = nlp.polynomials().tau;
  for (int i = 0; i < nlp.num_elements(); ++i) {
    r.element_times.push_back(nlp.element_start(e, i));
    for (std::size_t k = 0; k < tau.size(); ++k) add_node(i, int(k), tau[k]);
  }
  r.element_times.push_back(nlp.experiment(e).tf);
  add_node(nlp.num_elements(), 0, 1.0);  // b_{n_e}; inputs of the last element
  r.collocation_points = nlp.collocation_points();
  for (std::size_t c = 0; c < nlp.experiment(e).controls.size(); ++c) {
    r.control_values.emplace_back();
    const int per_element = nlp.experiment(e).controls[c].per_point ? nlp.num_points() : 1;
    for (int i = 0; i < nlp.num_elements(); ++i)
      for (int j = 0; j < per_element; ++j)
        r.control_values.back().push_back(v[std::size_t(nlp.control_var(e, int(c), i) + j)]);
  }
  auto start = std::chrono::steady_clock::now();
  r.check = resimulate(nlp, e, r, path);
  r.timings.resimulation = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace detail

Inputs optimal_inputs(const OptimalControlProblem& problem, const OptimizationResult& result,
                      std::size_t num_inputs) {
  return inputs_for(problem.fixed_inputs, problem.controls, result, num_inputs);
}

std::string optimization_summary_json(const OptimizationResult& r, const ModelInfo& info) {
  nlohmann::ordered_json j;
  j["status"] = std::string(to_string(r.status));
  j["message"] = r.message;
  j["retries"] = r.retries;
  j["objective"] = r.objective;
  j["iterations"] = r.iterations;
  auto finite = [](double x) { return std::isfinite(x) ? nlohmann::ordered_json(x) : nullptr; };
  j["kkt"] = {{"primal_infeasibility", finite(r.kkt.primal_infeasibility)},
              {"dual_infeasibility", finite(r.kkt.dual_infeasibility)},
              {"complementarity", finite(r.kkt.complementarity)}};
  j["nlp"] = {{"variables", r.size.variables}, {"constraints", r.size.constraints},
              {"jacobian_nonzeros", r.size.jacobian_nonzeros},
              {"hessian_nonzeros", r.size.hessian_nonzeros}};
  j["timings_seconds"] = {{"nlp_build", r.timings.nlp_build}, {"solve", r.timings.solve},
                          {"function_evaluations", r.timings.function_evaluations},
                          {"resimulation", r.timings.resimulation}};
  nlohmann::ordered_json params = nlohmann::ordered_json::object();
  for (std::size_t k = 0; k < r.parameters.size() && k < info.parameters.size(); ++k)
    params[info.parameters[k].name] = r.parameters[k];
  j["parameters"] = params;
  j["resimulation"] = {{"performed", r.check.performed},
                       {"message", r.check.message},
                       {"max_state_difference", r.check.max_state_difference},
                       {"worst_state", r.check.worst_state},
                       {"worst_state_time", r.check.worst_state_time},
                       {"max_bound_violation", r.check.max_bound_violation},
                       {"worst_bound", r.check.worst_bound},
                       {"worst_bound_time", r.check.worst_bound_time}};
  return j.dump(2) + "\n";
}

void write_optimization_result(const std::string& directory, const OptimizationResult& result,
                               const ModelInfo& info) {
  write_csv_atomic(directory + "/trajectories.csv", result.trajectories);
  write_csv_atomic(directory + "/resimulated.csv", result.check.resimulated);
  std::string summary = optimization_summary_json(result, info);
  write_file_atomic(directory + "/summary.json", [&](std::ostream& out) { out << summary; });
}

}  // namespace mo::runtime
