// Parameter estimation: one collocation NLP over all experiments with shared
// parameters and a weighted least-squares objective, then the statistics.
#include "mo/runtime/estimate.hpp"

#include "estimate_statistics.hpp"
#include "optimize_internal.hpp"
#include "output_terms.hpp"

#include <chrono>
#include <cmath>
#include <limits>

namespace mo::runtime {
namespace {

detail::ExperimentSetup experiment_setup(const EstimationExperiment& ex) {
  detail::ExperimentSetup s;
  if (ex.data.times.empty()) throw detail::ProblemError("an experiment has no measurement times");
  s.t0 = ex.t0;
  s.tf = ex.data.times.back();
  s.fixed_inputs = ex.inputs;
  return s;
}

void check_table(const MeasurementTable& d, const ModelInfo& info) {
  if (d.values.rows() != Eigen::Index(d.times.size()) ||
      d.values.cols() != Eigen::Index(d.outputs.size()) || d.sigma.size() != d.outputs.size())
    throw detail::ProblemError("measurement table: values must be times × outputs, one sigma per output");
  for (std::size_t r = 0; r < d.outputs.size(); ++r)
    if (d.outputs[r] >= info.outputs.size() || !(d.sigma[r] > 0.0))
      throw detail::ProblemError("measurement table: output index out of range or sigma not positive");
}

std::vector<detail::MeasuredSample> samples(const detail::CollocationNlp& nlp, int e,
                                            const MeasurementTable& d) {
  const std::size_t ny = nlp.info().outputs.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<detail::MeasuredSample> out;
  for (std::size_t k = 0; k < d.times.size(); ++k) {
    detail::MeasuredSample s{nlp.point_at(e, d.times[k]), std::vector<double>(ny, nan),
                             std::vector<double>(ny, 1.0)};
    if (d.times[k] < nlp.experiment(e).t0) throw detail::ProblemError("measurement before t0");
    for (std::size_t r = 0; r < d.outputs.size(); ++r)
      s.measured[d.outputs[r]] = d.values(Eigen::Index(k), Eigen::Index(r)),
      s.sigma[d.outputs[r]] = d.sigma[r];
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace

EstimationResult estimate_parameters(const Model& model, const EstimationProblem& problem) {
  EstimationResult result;
  try {
    auto start = std::chrono::steady_clock::now();
    if (problem.parameters.empty()) throw detail::ProblemError("no parameter to estimate");
    std::vector<detail::ExperimentSetup> setups;
    for (const EstimationExperiment& ex : problem.experiments) {
      check_table(ex.data, model.info());
      setups.push_back(experiment_setup(ex));
    }
    detail::CollocationNlp nlp(
        model, {problem.parameter_values, problem.parameters, problem.collocation}, setups);
    std::vector<detail::MeasuredSample> all;
    for (int e = 0; e < nlp.num_experiments(); ++e) {
      auto s = samples(nlp, e, problem.experiments[std::size_t(e)].data);
      all.insert(all.end(), s.begin(), s.end());
    }
    nlp.add_objective(std::make_unique<detail::LeastSquares>(std::move(all)));
    double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    detail::IpoptOutcome outcome = detail::solve_with_ipopt(nlp, problem.solver);
    for (int e = 0; e < nlp.num_experiments(); ++e) {
      result.experiments.push_back(detail::collect_result(nlp, outcome, e, {}));
      result.experiments.back().timings.nlp_build = build;
    }
    result.status = outcome.status, result.message = outcome.message;
    result.iterations = outcome.iterations, result.chi_square = outcome.objective;
    result.parameters = result.experiments.front().parameters;
    for (const FreeParameter& fp : problem.parameters) {
      result.names.push_back(model.info().parameters[fp.parameter].name);
      result.estimate.push_back(result.parameters[fp.parameter]);
    }
    detail::add_statistics(model, problem, result);
  } catch (const std::invalid_argument& e) {
    result.status = OptimizationStatus::invalid_problem;
    result.message = e.what();
  }
  return result;
}

}  // namespace mo::runtime
