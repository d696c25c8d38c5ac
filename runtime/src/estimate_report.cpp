// summary.json and trajectories of a parameter estimate.
#include "mo/runtime/estimate.hpp"

#include <nlohmann/json.hpp>

namespace mo::runtime {
namespace {

nlohmann::ordered_json matrix(const Eigen::MatrixXd& m) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    std::vector<double> row(std::size_t(m.cols()));
    for (Eigen::Index c = 0; c < m.cols(); ++c) row[std::size_t(c)] = m(r, c);
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

std::string estimation_summary_json(const EstimationResult& r) {
  nlohmann::ordered_json j;
  j["status"] = std::string(to_string(r.status));
  j["message"] = r.message;
  j["iterations"] = r.iterations;
  j["chi_square"] = r.chi_square;
  j["measurements"] = r.measurements;
  j["degrees_of_freedom"] = r.degrees_of_freedom;
  j["residual_variance"] = r.residual_variance;
  j["interval"] = "Student t, quantile " + std::to_string(r.t_quantile);
  nlohmann::ordered_json params = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < r.estimate.size(); ++k) {
    nlohmann::ordered_json p = {{"name", r.names[k]}, {"estimate", r.estimate[k]}};
    if (k < r.standard_error.size())
      p["standard_error"] = r.standard_error[k],
      p["interval"] = {r.confidence_interval[k].lo, r.confidence_interval[k].hi};
    params.push_back(p);
  }
  j["parameters"] = params;
  j["covariance"] = matrix(r.covariance);
  j["correlation"] = matrix(r.correlation);
  j["warnings"] = r.warnings;
  nlohmann::ordered_json experiments = nlohmann::ordered_json::array();
  for (const OptimizationResult& e : r.experiments)
    experiments.push_back({{"max_state_difference", e.check.max_state_difference},
                           {"worst_state", e.check.worst_state},
                           {"max_bound_violation", e.check.max_bound_violation},
                           {"replay_message", e.check.message}});
  j["experiments"] = experiments;
  return j.dump(2) + "\n";
}

void write_estimation_result(const std::string& directory, const EstimationResult& result) {
  for (std::size_t e = 0; e < result.experiments.size(); ++e)
    write_csv_atomic(directory + "/trajectories_" + std::to_string(e) + ".csv",
                     result.experiments[e].trajectories);
  std::string summary = estimation_summary_json(result);
  write_file_atomic(directory + "/summary.json", [&](std::ostream& out) { out << summary; });
}

}  // namespace mo::runtime
