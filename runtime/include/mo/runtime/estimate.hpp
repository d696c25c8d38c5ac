// Parameter estimation by weighted least squares over one or several experiments.
//
//   minimise_p  χ²(p) = Σ_e Σ_k Σ_r ((y_r^e(t_k; p) − m_kr^e) / σ_r^e)²   (NaN m skipped)
//   subject to  the dynamics of every experiment (collocation), p_lo ≤ p ≤ p_hi,
//
// the free parameters shared by all experiments, each experiment with its own
// input signals. At the estimate p̂, with N measurements and n free parameters:
//   F   = Σ S_yᵀ Σ⁻¹ S_y  from CVODES forward sensitivities (not the collocation),
//   s²  = χ²(p̂) / (N − n)  (residual variance; ≈ 1 when the σ are right),
//   Cov = s² F⁻¹,  CI = p̂ ± t_{1−α/2, N−n} · sqrt(Cov_ii)  (Student t).
#pragma once

#include "mo/runtime/optimize.hpp"

#include <Eigen/Dense>

namespace mo::runtime {

/// Measured outputs of one experiment: values(k, r) is output outputs[r] at times[k].
struct MeasurementTable {
  std::vector<double> times;         ///< ascending sample times
  std::vector<std::size_t> outputs;  ///< measured model outputs (columns)
  Eigen::MatrixXd values;            ///< times × outputs; NaN marks a missing sample
  std::vector<double> sigma;         ///< noise standard deviation per column, > 0
};

/// One experiment: how the plant was driven and what was measured.
struct EstimationExperiment {
  std::map<std::size_t, std::shared_ptr<const InputSignal>> inputs;  ///< every model input
  MeasurementTable data;  ///< the measurements
  double t0 = 0.0;        ///< start of the experiment (states from x0(p) here)
};

/// A least-squares estimation problem.
struct EstimationProblem {
  std::vector<EstimationExperiment> experiments;  ///< at least one
  std::vector<FreeParameter> parameters;          ///< the estimated parameters, shared
  std::vector<double> parameter_values;  ///< all parameter values (fixed ones); empty = defaults
  CollocationOptions collocation;        ///< per experiment; horizon t0 .. last sample time
  SolverOptions solver;                  ///< Ipopt settings
  double confidence = 0.95;              ///< confidence level of the intervals
};

/// The estimate with its uncertainty.
struct EstimationResult {
  OptimizationStatus status = OptimizationStatus::solver_error;  ///< of the optimisation
  std::string message;                 ///< solver message, or why the statistics are missing
  std::vector<std::string> names;      ///< names of the estimated parameters
  std::vector<double> estimate;        ///< p̂, one per FreeParameter
  std::vector<double> parameters;      ///< all parameter values at p̂
  double chi_square = 0.0;             ///< χ²(p̂) (the objective)
  int iterations = 0;                  ///< Ipopt iterations
  int measurements = 0;                ///< N: non-missing samples
  int degrees_of_freedom = 0;          ///< N − n
  double residual_variance = 0.0;      ///< s² = χ² / (N − n)
  Eigen::MatrixXd fisher;              ///< F at p̂ (n × n)
  Eigen::MatrixXd covariance;          ///< s² F⁻¹ (empty if F is singular)
  Eigen::MatrixXd correlation;         ///< Cov_ij / sqrt(Cov_ii Cov_jj)
  std::vector<double> standard_error;  ///< sqrt(Cov_ii)
  std::vector<Bounds> confidence_interval;  ///< p̂ ± t·se (Student t, N − n degrees of freedom)
  double t_quantile = 0.0;             ///< the Student-t quantile used
  std::vector<std::string> warnings;   ///< e.g. near-singular Fisher information, naming parameters
  std::vector<OptimizationResult> experiments;  ///< per experiment: trajectories and replay check
};

/// Estimates the parameters; never throws on solver failure (see status). An
/// inconsistent problem gives invalid_problem with a message.
EstimationResult estimate_parameters(const Model& model, const EstimationProblem& problem);

/// The estimate as a JSON document: status, message, iterations, χ², N, degrees of
/// freedom, s², per parameter the estimate, standard error and interval, the
/// covariance and correlation matrices, warnings, and each experiment's replay check.
std::string estimation_summary_json(const EstimationResult& result);
/// Writes summary.json (estimation_summary_json) and per experiment e
/// `trajectories_<e>.csv` into `directory` (which must exist), atomically.
/// Throws std::system_error on I/O failure.
void write_estimation_result(const std::string& directory, const EstimationResult& result);

/// The p-quantile of Student's t distribution with `dof` degrees of freedom
/// (Cornish–Fisher expansion around the normal quantile; error < 1e-3 for dof ≥ 3).
double student_t_quantile(double p, int dof);

}  // namespace mo::runtime
