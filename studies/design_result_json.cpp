// InputDesignResult ⇄ JSON; see design_result_json.hpp.
#include "design_result_json.hpp"

#include <cmath>
#include <limits>

namespace mo::tools {

using nlohmann::json;

namespace {

json num(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return v;
}

double num(const json& j) {
  if (!j.is_string()) return j.get<double>();
  const auto s = j.get<std::string>();
  if (s == "inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  return std::numeric_limits<double>::quiet_NaN();
}

json nums(const std::vector<double>& v) {
  json a = json::array();
  for (double x : v) a.push_back(num(x));
  return a;
}

std::vector<double> nums(const json& j) {
  std::vector<double> v;
  for (const auto& x : j) v.push_back(num(x));
  return v;
}

json matrix(const Eigen::MatrixXd& m) {
  std::vector<double> values(m.data(), m.data() + m.size());  // column-major
  return {{"rows", m.rows()}, {"cols", m.cols()}, {"values", nums(values)}};
}

Eigen::MatrixXd matrix(const json& j) {
  const std::vector<double> v = nums(j.at("values"));
  Eigen::MatrixXd m(j.at("rows").get<Eigen::Index>(), j.at("cols").get<Eigen::Index>());
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = v[static_cast<std::size_t>(i)];
  return m;
}

json table(const runtime::ResultTable& t) {
  std::vector<double> values;
  for (std::size_t k = 0; k < t.rows(); ++k) {
    const auto row = t.row(k);
    values.insert(values.end(), row.begin(), row.end());
  }
  return {{"names", t.names()}, {"times", nums(t.times())}, {"values", nums(values)}};
}

runtime::ResultTable table(const json& j) {
  runtime::ResultTable t(j.at("names").get<std::vector<std::string>>());
  const std::vector<double> times = nums(j.at("times")), values = nums(j.at("values"));
  const std::size_t width = t.names().size();
  for (std::size_t k = 0; k < times.size(); ++k)
    t.add_row(times[k], std::span<const double>(values.data() + k * width, width));
  return t;
}

json check_json(const runtime::ResimulationCheck& c) {
  return {{"performed", c.performed},
          {"message", c.message},
          {"max_state_difference", num(c.max_state_difference)},
          {"worst_state", c.worst_state},
          {"worst_state_time", num(c.worst_state_time)},
          {"max_bound_violation", num(c.max_bound_violation)},
          {"worst_bound", c.worst_bound},
          {"worst_bound_time", num(c.worst_bound_time)},
          {"resimulated", table(c.resimulated)}};
}

runtime::ResimulationCheck check_of(const json& j) {
  runtime::ResimulationCheck c;
  c.performed = j.at("performed").get<bool>();
  c.message = j.at("message").get<std::string>();
  c.max_state_difference = num(j.at("max_state_difference"));
  c.worst_state = j.at("worst_state").get<std::string>();
  c.worst_state_time = num(j.at("worst_state_time"));
  c.max_bound_violation = num(j.at("max_bound_violation"));
  c.worst_bound = j.at("worst_bound").get<std::string>();
  c.worst_bound_time = num(j.at("worst_bound_time"));
  c.resimulated = table(j.at("resimulated"));
  return c;
}

json optimization_json(const runtime::OptimizationResult& r) {
  json controls = json::array();
  for (const auto& c : r.control_values) controls.push_back(nums(c));
  return {{"status", static_cast<int>(r.status)},
          {"message", r.message},
          {"retries", r.retries},
          {"objective", num(r.objective)},
          {"iterations", r.iterations},
          {"kkt", nums(std::vector<double>{r.kkt.primal_infeasibility, r.kkt.dual_infeasibility, r.kkt.complementarity})},
          {"size", {r.size.variables, r.size.constraints, r.size.jacobian_nonzeros, r.size.hessian_nonzeros}},
          {"timings", nums(std::vector<double>{r.timings.nlp_build, r.timings.solve, r.timings.function_evaluations,
                            r.timings.resimulation})},
          {"trajectories", table(r.trajectories)},
          {"parameters", nums(r.parameters)},
          {"element_times", nums(r.element_times)},
          {"control_values", controls},
          {"check", check_json(r.check)}};
}

runtime::OptimizationResult optimization_of(const json& j) {
  runtime::OptimizationResult r;
  r.status = static_cast<runtime::OptimizationStatus>(j.at("status").get<int>());
  r.message = j.at("message").get<std::string>();
  r.retries = j.at("retries").get<std::vector<std::string>>();
  r.objective = num(j.at("objective"));
  r.iterations = j.at("iterations").get<int>();
  const auto kkt = nums(j.at("kkt"));
  r.kkt = {kkt.at(0), kkt.at(1), kkt.at(2)};
  const auto size = j.at("size").get<std::vector<int>>();
  r.size = {size.at(0), size.at(1), size.at(2), size.at(3)};
  const auto t = nums(j.at("timings"));
  r.timings = {t.at(0), t.at(1), t.at(2), t.at(3)};
  r.trajectories = table(j.at("trajectories"));
  r.parameters = nums(j.at("parameters"));
  r.element_times = nums(j.at("element_times"));
  for (const auto& c : j.at("control_values")) r.control_values.push_back(nums(c));
  r.check = check_of(j.at("check"));
  return r;
}

json attempts_json(const std::vector<runtime::DesignAttempt>& attempts) {
  json a = json::array();
  for (const auto& t : attempts)
    a.push_back({{"hessian", static_cast<int>(t.hessian)},
                 {"status", static_cast<int>(t.status)},
                 {"iterations", t.iterations},
                 {"kkt", nums(std::vector<double>{t.kkt.primal_infeasibility, t.kkt.dual_infeasibility,
                                                  t.kkt.complementarity})},
                 {"solve_seconds", num(t.solve_seconds)},
                 {"information_collocation", num(t.information_collocation)},
                 {"information_resimulated", num(t.information_resimulated)},
                 {"kept", t.kept}});
  return a;
}

std::vector<runtime::DesignAttempt> attempts_of(const json& j) {
  std::vector<runtime::DesignAttempt> out;
  for (const auto& a : j) {
    runtime::DesignAttempt t;
    t.hessian = static_cast<runtime::HessianMode>(a.at("hessian").get<int>());
    t.status = static_cast<runtime::OptimizationStatus>(a.at("status").get<int>());
    t.iterations = a.at("iterations").get<int>();
    const auto kkt = nums(a.at("kkt"));
    t.kkt = {kkt.at(0), kkt.at(1), kkt.at(2)};
    t.solve_seconds = num(a.at("solve_seconds"));
    t.information_collocation = num(a.at("information_collocation"));
    t.information_resimulated = num(a.at("information_resimulated"));
    t.kept = a.at("kept").get<bool>();
    out.push_back(t);
  }
  return out;
}

}  // namespace

json design_result_to_json(const runtime::InputDesignResult& r) {
  return {{"optimization", optimization_json(r.optimization)},
          {"fisher_collocation", matrix(r.fisher_collocation)},
          {"fisher_resimulated", matrix(r.fisher_resimulated)},
          {"information_collocation", num(r.information_collocation)},
          {"information_resimulated", num(r.information_resimulated)},
          {"start_information", nums(r.start_information)},
          {"attempts", attempts_json(r.attempts)}};
}

runtime::InputDesignResult design_result_from_json(const json& j) {
  runtime::InputDesignResult r;
  r.optimization = optimization_of(j.at("optimization"));
  r.fisher_collocation = matrix(j.at("fisher_collocation"));
  r.fisher_resimulated = matrix(j.at("fisher_resimulated"));
  r.information_collocation = num(j.at("information_collocation"));
  r.information_resimulated = num(j.at("information_resimulated"));
  r.start_information = nums(j.at("start_information"));
  r.attempts = attempts_of(j.at("attempts"));
  return r;
}

}  // namespace mo::tools
