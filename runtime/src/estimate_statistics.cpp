#include "estimate_statistics.hpp"

#include "mo/runtime/simulate.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

namespace mo::runtime {
namespace {

double normal_quantile(double p) {
  double x = 0.0;
  for (int it = 0; it < 50; ++it) {
    double cdf = 0.5 * std::erfc(-x / std::numbers::sqrt2);
    double pdf = std::exp(-0.5 * x * x) / std::sqrt(2.0 * std::numbers::pi);
    double step = (cdf - p) / pdf;
    x -= step;
    if (std::abs(step) < 1e-14) break;
  }
  return x;
}

// Σ over experiments of S_yᵀ Σ⁻¹ S_y at the samples, from CVODES sensitivities;
// counts the non-missing samples. Returns false (with `why`) if a simulation fails.
bool fisher_from_sensitivities(const Model& model, const EstimationProblem& problem,
                               const EstimationResult& result, Eigen::MatrixXd& f, int& samples,
                               std::string& why) {
  std::vector<std::size_t> params;
  for (const FreeParameter& fp : problem.parameters) params.push_back(fp.parameter);
  SimulationOptions options;
  options.relative_tolerance = 1e-10, options.absolute_tolerance = 1e-10;
  options.sensitivities.method = SensitivityMethod::cvodes_analytic;
  options.sensitivities.parameters = params;
  f = Eigen::MatrixXd::Zero(Eigen::Index(params.size()), Eigen::Index(params.size()));
  samples = 0;
  for (const EstimationExperiment& ex : problem.experiments) {
    Inputs inputs;
    for (std::size_t i = 0; i < model.info().inputs.size(); ++i) inputs.add(shared_input(ex.inputs.at(i)));
    std::vector<double> times{ex.t0};
    times.insert(times.end(), ex.data.times.begin(), ex.data.times.end());
    std::unique_ptr<Model> m = model.clone();
    SimulationResult sim = simulate(*m, inputs, result.parameters, OutputGrid::at(times), options);
    if (!sim.ok() || sim.output_sensitivities.size() != times.size()) {
      why = std::string(to_string(sim.status)) + ": " + sim.message;
      return false;
    }
    for (std::size_t k = 0; k < ex.data.times.size(); ++k)
      for (std::size_t r = 0; r < ex.data.outputs.size(); ++r) {
        if (std::isnan(ex.data.values(Eigen::Index(k), Eigen::Index(r)))) continue;
        Eigen::RowVectorXd row = sim.output_sensitivities[k + 1].row(Eigen::Index(ex.data.outputs[r]));
        f += row.transpose() * row / (ex.data.sigma[r] * ex.data.sigma[r]);
        ++samples;
      }
  }
  return true;
}

// Names the parameters that dominate the weakest direction of the scaled F.
void warn_if_near_singular(const Eigen::MatrixXd& f, EstimationResult& result) {
  Eigen::VectorXd d = f.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(d.asDiagonal() * f * d.asDiagonal());
  const double lmin = eig.eigenvalues()[0], lmax = eig.eigenvalues().maxCoeff();
  if (lmin > 1e-8 * lmax && f.diagonal().minCoeff() > 0.0) return;
  std::ostringstream msg;
  msg << "near-singular Fisher information (scaled eigenvalue ratio " << lmin / lmax
      << "): the data hardly determine the combination of";
  for (Eigen::Index j = 0; j < eig.eigenvectors().rows(); ++j)
    if (std::abs(eig.eigenvectors()(j, 0)) > 0.3 || f(j, j) <= 0.0)
      msg << ' ' << result.names[std::size_t(j)];
  result.warnings.push_back(msg.str());
}

}  // namespace

double student_t_quantile(double p, int dof) {
  const double z = normal_quantile(p), n = dof;
  if (dof < 1) return std::numeric_limits<double>::quiet_NaN();
  const double z3 = z * z * z, z5 = z3 * z * z, z7 = z5 * z * z, z9 = z7 * z * z;
  return z + (z3 + z) / (4 * n) + (5 * z5 + 16 * z3 + 3 * z) / (96 * n * n) +
         (3 * z7 + 19 * z5 + 17 * z3 - 15 * z) / (384 * n * n * n) +
         (79 * z9 + 776 * z7 + 1482 * z5 - 1920 * z3 - 945 * z) / (92160 * n * n * n * n);
}

namespace detail {

void add_statistics(const Model& model, const EstimationProblem& problem, EstimationResult& r) {
  std::string why;
  if (!fisher_from_sensitivities(model, problem, r, r.fisher, r.measurements, why)) {
    r.warnings.push_back("no statistics: the sensitivity simulation failed: " + why);
    return;
  }
  const auto n = Eigen::Index(r.estimate.size());
  r.degrees_of_freedom = r.measurements - int(n);
  if (r.degrees_of_freedom < 1) {
    r.warnings.push_back("no statistics: fewer measurements than parameters");
    return;
  }
  r.residual_variance = r.chi_square / r.degrees_of_freedom;
  warn_if_near_singular(r.fisher, r);
  Eigen::LLT<Eigen::MatrixXd> llt(r.fisher);
  if (llt.info() != Eigen::Success) {
    r.warnings.push_back("no covariance: the Fisher information is singular");
    return;
  }
  r.covariance = r.residual_variance * llt.solve(Eigen::MatrixXd::Identity(n, n));
  r.t_quantile = student_t_quantile(1.0 - (1.0 - problem.confidence) / 2.0, r.degrees_of_freedom);
  Eigen::VectorXd se = r.covariance.diagonal().cwiseSqrt();
  r.correlation = se.cwiseInverse().asDiagonal() * r.covariance * se.cwiseInverse().asDiagonal();
  for (Eigen::Index j = 0; j < n; ++j) {
    r.standard_error.push_back(se[j]);
    r.confidence_interval.push_back({r.estimate[std::size_t(j)] - r.t_quantile * se[j],
                                     r.estimate[std::size_t(j)] + r.t_quantile * se[j]});
    for (Eigen::Index k = 0; k < j; ++k)
      if (std::abs(r.correlation(j, k)) > 0.99)
        r.warnings.push_back("parameters " + r.names[std::size_t(j)] + " and " +
                             r.names[std::size_t(k)] + " are correlated (" +
                             std::to_string(r.correlation(j, k)) + ")");
  }
}

}  // namespace detail
}  // namespace mo::runtime
