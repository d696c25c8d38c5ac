// The optimal-control driver: transcribe, solve, collect, re-simulate.
#include "mo/runtime/optimize.hpp"

#include "optimize_internal.hpp"
#include "control_changes.hpp"
#include "output_terms.hpp"

#include <chrono>
#include <iomanip>

namespace mo::runtime {
namespace detail {

ExperimentSetup experiment_setup(const OptimalControlProblem& problem) {
  return ExperimentSetup{problem.t0,           problem.tf,           problem.controls,
                         problem.fixed_inputs, problem.state_bounds, problem.final_state};
}

NlpSetup nlp_setup(const OptimalControlProblem& problem) {
  return NlpSetup{problem.parameters, problem.free_parameters, problem.collocation};
}

namespace {

void check_output(const CollocationNlp& nlp, std::size_t output, const char* where) {
  if (output >= nlp.info().outputs.size())
    throw ProblemError(std::string(where) + ": output index " + std::to_string(output) +
                       " out of range");
}

// Every collocation point of experiment e.
std::vector<PointRef> collocation_points(const CollocationNlp& nlp, int e) {
  std::vector<PointRef> points;
  for (int i = 0; i < nlp.num_elements(); ++i)
    for (int j = 1; j <= nlp.num_points(); ++j)
      points.push_back(nlp.point(e, i, nlp.polynomials().tau[std::size_t(j)]));
  return points;
}

}  // namespace

void add_problem_terms(CollocationNlp& nlp, const OptimalControlProblem& problem, int e) {
  std::vector<OutputAtPoint> objective, rows;
  const PointRef final_point = nlp.point(e, nlp.num_elements() - 1, 1.0);
  for (const MayerTerm& m : problem.mayer) {
    check_output(nlp, m.output, "Mayer term");
    objective.push_back({final_point, m.output, m.weight, {}});
  }
  const std::vector<PointRef> points = collocation_points(nlp, e);
  for (const LagrangeTerm& l : problem.lagrange) {
    check_output(nlp, l.output, "Lagrange term");
    for (std::size_t q = 0; q < points.size(); ++q) {
      double w = nlp.polynomials().weights[q % std::size_t(nlp.num_points())];
      const PointRef& pt = points[q];
      objective.push_back({pt, l.output, l.weight * w * nlp.element_length(e, pt.element), {}});
    }
  }
  for (const PathConstraint& c : problem.path_constraints) {
    check_output(nlp, c.output, "path constraint");
    for (const PointRef& pt : points) rows.push_back({pt, c.output, 1.0, c.bounds});
  }
  for (const PointConstraint& c : problem.point_constraints) {
    check_output(nlp, c.output, "point constraint");
    if (c.time < problem.t0 || c.time > problem.tf)
      throw ProblemError("point constraint time outside [t0, tf]");
    rows.push_back({nlp.point_at(e, c.time), c.output, 1.0, c.bounds});
  }
  if (!objective.empty()) nlp.add_objective(std::make_unique<WeightedOutputs>(std::move(objective)));
  if (!rows.empty()) nlp.add_constraints(std::make_unique<OutputConstraints>(std::move(rows)));
  if (ControlChanges::needed(nlp, e)) nlp.add_constraints(std::make_unique<ControlChanges>(nlp, e));
}

OptimizationResult invalid_problem_result(const std::string& message) {
  OptimizationResult result;
  result.status = OptimizationStatus::invalid_problem;
  result.message = message;
  return result;
}

}  // namespace detail

std::string_view to_string(OptimizationStatus status) {
  switch (status) {
  case OptimizationStatus::success: return "success";
  case OptimizationStatus::acceptable: return "acceptable";
  case OptimizationStatus::infeasible: return "infeasible";
  case OptimizationStatus::iteration_limit: return "iteration_limit";
  case OptimizationStatus::time_limit: return "time_limit";
  case OptimizationStatus::evaluation_error: return "evaluation_error";
  case OptimizationStatus::linear_solver_failure: return "linear_solver_failure";
  case OptimizationStatus::restoration_failure: return "restoration_failure";
  case OptimizationStatus::user_stop: return "user_stop";
  case OptimizationStatus::stalled: return "stalled";
  case OptimizationStatus::invalid_problem: return "invalid_problem";
  case OptimizationStatus::solver_error: return "solver_error";
  }
  return "unknown";
}

ProgressCallback print_progress(std::ostream& out) {
  return [&out](const IterationInfo& it) {
    out << std::setw(5) << it.iteration << (it.restoration ? "r " : "  ") << std::scientific
        << std::setprecision(8) << std::setw(16) << it.objective << std::setprecision(2)
        << std::setw(10) << it.inf_pr << std::setw(10) << it.inf_du << std::defaultfloat << '\n';
    return true;
  };
}

OptimizationResult solve(const Model& model, const OptimalControlProblem& problem) {
  auto start = std::chrono::steady_clock::now();
  try {
    detail::CollocationNlp nlp(model, detail::nlp_setup(problem),
                               {detail::experiment_setup(problem)});
    detail::add_problem_terms(nlp, problem, 0);
    double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    detail::IpoptOutcome outcome = detail::solve_with_ipopt(nlp, problem.solver);
    OptimizationResult result = detail::collect_result(nlp, outcome, 0, problem.path_constraints);
    result.timings.nlp_build = build;
    return result;
  } catch (const detail::ProblemError& e) {
    return detail::invalid_problem_result(e.what());
  } catch (const std::invalid_argument& e) {
    return detail::invalid_problem_result(e.what());
  }
}

}  // namespace mo::runtime
