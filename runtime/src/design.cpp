// Input design: the collocation problem with a Fisher criterion, several
// starts, and the replay of the designed input on CVODES.
#include "mo/runtime/design.hpp"

#include "design_fisher_nlp.hpp"
#include "fisher_terms.hpp"
#include "mo/runtime/simulate.hpp"
#include "optimize_internal.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace mo::runtime {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// The objective and constraints of the criterion on the Fisher matrix of the
// trajectory (limited-memory Hessian); returns F of a solution.
std::function<Eigen::MatrixXd(std::span<const double>)> add_trajectory_criterion(
    detail::CollocationNlp& nlp, const InputDesignProblem& problem) {
  auto fisher = std::make_shared<const detail::FisherEvaluator>(nlp, problem.measurements,
                                                                problem.parameters);
  if (problem.criterion == DesignCriterion::E) {
    auto epigraph = std::make_unique<detail::FisherEpigraph>(nlp, fisher);
    nlp.add_objective(std::make_unique<detail::MaximiseVariable>(epigraph->epigraph_variable()));
    nlp.add_constraints(std::move(epigraph));
  } else {
    nlp.add_objective(std::make_unique<detail::FisherCriterion>(fisher, problem.criterion));
    if (problem.criterion == DesignCriterion::A) {  // trace F⁻¹ is tiny: scale it to ~1
      double a0 = std::abs(criterion_information(DesignCriterion::A, fisher->fisher(nlp, nlp.initial_guess())));
      if (std::isfinite(a0) && a0 > 0.0) nlp.set_objective_scaling(1.0 / a0);
    }
  }
  return [&nlp, fisher](std::span<const double> v) { return fisher->fisher(nlp, v); };
}

// The criterion on lifted F variables (design_fisher_nlp.hpp: exact Hessians).
std::function<Eigen::MatrixXd(std::span<const double>)> add_lifted_criterion(
    detail::CollocationNlp& nlp, const InputDesignProblem& problem,
    std::vector<std::vector<std::size_t>> sensitivity_outputs) {
  const DesignCriterion c = problem.criterion;
  auto lifted = std::make_unique<detail::LiftedFisher>(
      nlp, problem.measurements, std::move(sensitivity_outputs),
      c == DesignCriterion::A || c == DesignCriterion::D);
  const detail::LiftedFisher& f = *lifted;
  nlp.add_constraints(std::move(lifted));
  if (c == DesignCriterion::E) {
    nlp.set_objective_scaling(1.0 / f.magnitude());  // t is of the order of F's entries
    auto epigraph = std::make_unique<detail::FisherVariableEpigraph>(nlp, f);
    nlp.add_objective(std::make_unique<detail::MaximiseVariable>(epigraph->epigraph_variable()));
    nlp.add_constraints(std::move(epigraph));
  } else {
    nlp.add_objective(std::make_unique<detail::FisherVariableCriterion>(f, c));
    // Scale the criterion to ~1 at the start: trace F⁻¹ is tiny, trace F large.
    double c0 = std::abs(criterion_information(c, f.fisher_variables(nlp.initial_guess())));
    if (c == DesignCriterion::T) nlp.set_objective_scaling(1.0 / f.magnitude());
    if (c == DesignCriterion::A && std::isfinite(c0) && c0 > 0.0) nlp.set_objective_scaling(1.0 / c0);
  }
  return [&nlp, &f](std::span<const double> v) { return f.trajectory_fisher(nlp, v); };
}

InputDesignResult design_once(const Model& model, const InputDesignProblem& problem) {
  auto start = std::chrono::steady_clock::now();
  InputDesignResult out;
  const OptimalControlProblem& ocp = problem.ocp;
  detail::CollocationNlp nlp(model, detail::nlp_setup(ocp), {detail::experiment_setup(ocp)});
  detail::add_problem_terms(nlp, ocp, 0);
  auto outputs = detail::sensitivity_outputs(model.info(), problem.measurements, problem.parameters);
  // The lifted F with exact Hessians where the model has them; with limited
  // memory the criterion on the trajectory (issue 11's earlier formulation),
  // unless the model has sensitivity outputs only (a multi-phase model).
  const bool lifted = outputs && ((ocp.solver.hessian != HessianMode::limited_memory &&
                                   model.provides_hessian(Hessian::f) && model.provides_hessian(Hessian::h)) ||
                                  !detail::has_sensitivity_states(model.info(), problem.parameters));
  auto fisher = lifted ? add_lifted_criterion(nlp, problem, std::move(*outputs))
                       : add_trajectory_criterion(nlp, problem);
  double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const bool exact = ocp.solver.hessian != HessianMode::limited_memory && nlp.exact_hessian_possible();
  // MUMPS's own scaling misjudges the inertia of the design's KKT matrices
  // (docs/design-formulation.md, "Linear algebra"); the NLP is scaled by us.
  SolverOptions solver = ocp.solver;
  solver.mumps_scaling = false;
  detail::IpoptOutcome outcome = detail::solve_with_ipopt(nlp, solver);
  out.optimization = detail::collect_result(nlp, outcome, 0, ocp.path_constraints);
  out.optimization.timings.nlp_build = build;
  out.fisher_collocation = fisher(outcome.solution);
  out.information_collocation = criterion_information(problem.criterion, out.fisher_collocation);
  out.information_resimulated = nan;
  try {
    Inputs inputs = optimal_inputs(ocp, out.optimization, model.info().inputs.size());
    out.fisher_resimulated = fisher_information(model, inputs, out.optimization.parameters, ocp.t0,
                                                problem.measurements, problem.parameters);
    out.information_resimulated = criterion_information(problem.criterion, out.fisher_resimulated);
  } catch (const std::runtime_error& e) {
    out.optimization.check.message += std::string(" (Fisher replay: ") + e.what() + ")";
  }
  const OptimizationResult& o = out.optimization;
  out.attempts = {{exact ? HessianMode::exact : HessianMode::limited_memory, o.status, o.iterations,
                   o.kkt, o.timings.solve, out.information_collocation,
                   out.information_resimulated, true}};
  return out;
}

// Ends that a limited-memory solve from the same start may mend: the exact
// Hessian's Newton steps wandered (iteration limit), or stopped short.
bool fallback_helps(OptimizationStatus s) {
  return s == OptimizationStatus::iteration_limit || s == OptimizationStatus::restoration_failure ||
         s == OptimizationStatus::stalled;
}

std::string attempt_text(const DesignAttempt& a) {
  char kkt[128];
  std::snprintf(kkt, sizeof kkt, "primal %.2e, dual %.2e, complementarity %.2e",
                a.kkt.primal_infeasibility, a.kkt.dual_infeasibility, a.kkt.complementarity);
  return std::string(to_string(a.status)) + " after " + std::to_string(a.iterations) +
         " iterations (KKT residuals: " + kkt + ")";
}

// The Ipopt log of the fallback beside the first one's: ipopt.log → ipopt_limited_memory.log.
std::string fallback_log(const std::string& log) {
  if (log.empty()) return log;
  std::filesystem::path p(log);
  return (p.parent_path() / (p.stem().string() + "_limited_memory" + p.extension().string())).string();
}

// design_once, then the limited-memory fallback when the exact solve failed
// (docs/design-formulation.md, "Fallback"): from the same start, not from the
// failed iterate, which after an iteration limit is often far from feasible.
InputDesignResult design_with_fallback(const Model& model, const InputDesignProblem& problem) {
  InputDesignResult first = design_once(model, problem);
  const DesignAttempt& a = first.attempts.front();
  if (!problem.hessian_fallback || a.hessian != HessianMode::exact || !fallback_helps(a.status))
    return first;
  InputDesignProblem lbfgs = problem;
  lbfgs.ocp.solver.hessian = HessianMode::limited_memory;
  lbfgs.ocp.solver.log_file = fallback_log(problem.ocp.solver.log_file);
  InputDesignResult second = design_once(model, lbfgs);
  const bool keep_second = second.optimization.ok();
  InputDesignResult out = keep_second ? std::move(second) : std::move(first);
  InputDesignResult& other = keep_second ? first : second;
  DesignAttempt exact_attempt = keep_second ? other.attempts.front() : out.attempts.front();
  DesignAttempt lbfgs_attempt = keep_second ? out.attempts.front() : other.attempts.front();
  exact_attempt.kept = !keep_second, lbfgs_attempt.kept = keep_second;
  out.attempts = {exact_attempt, lbfgs_attempt};
  OptimizationTimings& t = out.optimization.timings;
  const OptimizationTimings& u = other.optimization.timings;
  t.nlp_build += u.nlp_build, t.solve += u.solve, t.function_evaluations += u.function_evaluations;
  const std::string line = "exact Hessian ended " + attempt_text(exact_attempt) +
                           "; limited-memory Hessian from the same start ended " +
                           attempt_text(lbfgs_attempt) + "; kept the " +
                           (keep_second ? "limited-memory" : "exact-Hessian") + " design";
  out.optimization.retries.push_back(line);
  out.optimization.message += " (" + line + ")";
  return out;
}

}  // namespace

std::vector<double> MeasurementDesign::uniform_times(double t0, double tf, std::size_t count) {
  std::vector<double> times;
  for (std::size_t k = 1; k <= count; ++k) times.push_back(t0 + double(k) * (tf - t0) / double(count));
  return times;
}

double criterion_information(DesignCriterion criterion, const Eigen::MatrixXd& f) {
  switch (criterion) {
  case DesignCriterion::T: return f.trace();
  case DesignCriterion::E: return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(f).eigenvalues().minCoeff();
  case DesignCriterion::D:
  case DesignCriterion::A: {
    Eigen::LLT<Eigen::MatrixXd> llt(f);
    if (llt.info() != Eigen::Success) return nan;
    if (criterion == DesignCriterion::A) return -llt.solve(Eigen::MatrixXd::Identity(f.rows(), f.cols())).trace();
    return 2.0 * Eigen::MatrixXd(llt.matrixL()).diagonal().array().log().sum();
  }
  }
  return nan;
}

Eigen::MatrixXd fisher_information(const Model& model, const Inputs& inputs,
                                   std::span<const double> p, double t0,
                                   const MeasurementDesign& m,
                                   const std::vector<std::size_t>& parameters) {
  if (m.sigma.size() != m.outputs.size())
    throw std::invalid_argument("fisher_information: one sigma per measured output");
  std::vector<double> times{t0};
  times.insert(times.end(), m.times.begin(), m.times.end());
  SimulationOptions options;
  options.relative_tolerance = 1e-10, options.absolute_tolerance = 1e-10;
  options.sensitivities.method = SensitivityMethod::model_states;
  options.sensitivities.parameters = parameters;
  std::unique_ptr<Model> sim_model = model.clone();
  SimulationResult sim = simulate(*sim_model, inputs, p, OutputGrid::at(times), options);
  if (!sim.ok() || sim.output_sensitivities.size() != times.size())
    throw std::runtime_error("simulation for the Fisher information failed: " +
                             std::string(to_string(sim.status)) + ": " + sim.message);
  const auto n = Eigen::Index(parameters.size());
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(n, n);
  for (std::size_t k = 1; k < times.size(); ++k) {
    const Eigen::MatrixXd& sy = sim.output_sensitivities[k];
    for (std::size_t r = 0; r < m.outputs.size(); ++r) {
      Eigen::RowVectorXd row = sy.row(Eigen::Index(m.outputs[r]));
      f += row.transpose() * row / (m.sigma[r] * m.sigma[r]);
    }
  }
  return f;
}

InputDesignResult design_input(const Model& model, const InputDesignProblem& problem) {
  try {
    if (problem.starts.empty()) return design_with_fallback(model, problem);
    if (problem.ocp.controls.empty())
      throw detail::ProblemError("several starts need at least one control");
    InputDesignResult best;
    std::vector<double> reached;
    for (const auto& start : problem.starts) {
      if (problem.on_start)
        problem.on_start(reached.size(), problem.starts.size(),
                         best.optimization.ok() ? best.information_collocation : nan);
      InputDesignProblem one = problem;
      one.starts.clear();
      one.ocp.controls[0].initial_guess = start;
      InputDesignResult r = design_with_fallback(model, one);
      reached.push_back(r.optimization.ok() ? r.information_collocation : nan);
      bool better = r.optimization.ok() &&
                    (!best.optimization.ok() || r.information_collocation > best.information_collocation);
      if (reached.size() == 1 || better) best = std::move(r);
    }
    best.start_information = std::move(reached);
    return best;
  } catch (const std::invalid_argument& e) {  // ProblemError and bad option values
    InputDesignResult r;
    r.optimization = detail::invalid_problem_result(e.what());
    return r;
  }
}

}  // namespace mo::runtime
