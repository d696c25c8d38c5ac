// Result tables, atomic file writing and JSON summaries.
#include "mo/runtime/result.hpp"

#include <nlohmann/json.hpp>

#include <cerrno>
#include <charconv>
#include <fcntl.h>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>
#include <system_error>
#include <unistd.h>

namespace mo::runtime {

void ResultTable::add_row(double t, std::span<const double> values) {
  if (values.size() != names_.size())
    throw std::invalid_argument("ResultTable::add_row: " + std::to_string(values.size()) +
                                " values for " + std::to_string(names_.size()) + " columns");
  times_.push_back(t);
  values_.insert(values_.end(), values.begin(), values.end());
}

std::span<const double> ResultTable::row(std::size_t k) const {
  return std::span<const double>(values_).subspan(k * names_.size(), names_.size());
}

std::vector<double> ResultTable::column(std::string_view name) const {
  for (std::size_t j = 0; j < names_.size(); ++j) {
    if (names_[j] != name) continue;
    std::vector<double> out;
    out.reserve(rows());
    for (std::size_t k = 0; k < rows(); ++k) out.push_back(at(k, j));
    return out;
  }
  throw std::out_of_range("ResultTable::column: no column named '" + std::string(name) + "'");
}

std::string_view to_string(SimulationStatus status) {
  switch (status) {
  case SimulationStatus::success: return "success";
  case SimulationStatus::terminated_by_model: return "terminated_by_model";
  case SimulationStatus::invalid_problem: return "invalid_problem";
  case SimulationStatus::too_much_work: return "too_much_work";
  case SimulationStatus::too_much_accuracy: return "too_much_accuracy";
  case SimulationStatus::error_test_failure: return "error_test_failure";
  case SimulationStatus::convergence_failure: return "convergence_failure";
  case SimulationStatus::linear_solver_failure: return "linear_solver_failure";
  case SimulationStatus::rhs_failure: return "rhs_failure";
  case SimulationStatus::event_indicator_failure: return "event_indicator_failure";
  case SimulationStatus::event_iteration_limit: return "event_iteration_limit";
  case SimulationStatus::event_limit: return "event_limit";
  case SimulationStatus::solver_error: return "solver_error";
  }
  return "unknown";  // unreachable for valid enumerators; -Werror=switch guards additions
}

ResultTable sensitivity_table(const SimulationResult& result, const ModelInfo& info) {
  if (result.state_sensitivities.empty()) return {};
  const auto& params = result.sensitivity_parameters;
  const auto nsx = static_cast<std::size_t>(result.state_sensitivities.front().rows());
  std::vector<std::string> names;
  for (std::size_t i = 0; i < nsx; ++i)
    for (std::size_t j : params)
      names.push_back("d(" + info.states[i].name + ")/d(" + info.parameters[j].name + ")");
  for (const auto& y : info.outputs)
    for (std::size_t j : params)
      names.push_back("d(" + y.name + ")/d(" + info.parameters[j].name + ")");
  ResultTable table(std::move(names));
  std::vector<double> row;
  for (std::size_t k = 0; k < result.state_sensitivities.size(); ++k) {
    row.clear();
    for (const Eigen::MatrixXd* m : {&result.state_sensitivities[k], &result.output_sensitivities[k]})
      for (Eigen::Index i = 0; i < m->rows(); ++i)
        for (Eigen::Index j = 0; j < m->cols(); ++j) row.push_back((*m)(i, j));
    table.add_row(result.trajectory.times()[k], row);
  }
  return table;
}

namespace {

[[noreturn]] void throw_errno(const std::string& what, const std::string& path) {
  throw std::system_error(errno, std::generic_category(), what + " '" + path + "'");
}

void write_all(int fd, std::string_view bytes, const std::string& path) {
  while (!bytes.empty()) {
    ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      throw_errno("cannot write temporary file for", path);
    }
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
}

void append_number(std::string& out, double v) {
  char buf[32];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  (void)ec;  // 32 chars always suffice for the shortest round-trip form
  out.append(buf, end);
}

// A column name as a CSV field: quoted (RFC 4180) when it holds a comma or
// a quote, as array elements of matrices do (`a[1,2]`).
std::string csv_name(const std::string& name) {
  if (name.find_first_of(",\"") == std::string::npos) return name;
  std::string out = "\"";
  for (char c : name) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace

void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& write) {
  std::ostringstream buffer;
  write(buffer);  // a throwing writer leaves no file behind: nothing was created yet
  const std::string bytes = std::move(buffer).str();

  std::filesystem::path target(path);
  std::filesystem::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  std::string temp = (dir / ("." + target.filename().string() + ".tmp.XXXXXX")).string();
  int fd = ::mkstemp(temp.data());
  if (fd < 0) throw_errno("cannot create temporary file for", path);
  try {
    write_all(fd, bytes, path);
    if (::fchmod(fd, 0644) != 0) throw_errno("cannot set mode of temporary file for", path);
    if (::fsync(fd) != 0) throw_errno("cannot fsync temporary file for", path);
    if (::close(fd) != 0) {
      fd = -1;
      throw_errno("cannot close temporary file for", path);
    }
    fd = -1;
    if (::rename(temp.c_str(), path.c_str()) != 0) throw_errno("cannot rename onto", path);
  } catch (...) {
    if (fd >= 0) ::close(fd);
    ::unlink(temp.c_str());
    throw;
  }
  // Make the rename itself durable; failure here cannot undo it, so it is ignored.
  int dir_fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dir_fd >= 0) {
    ::fsync(dir_fd);
    ::close(dir_fd);
  }
}

void write_csv_atomic(const std::string& path, const ResultTable& table) {
  write_file_atomic(path, [&](std::ostream& out) {
    std::string line = "time";
    for (const auto& name : table.names()) {
      line += ',';
      line += csv_name(name);
    }
    out << line << '\n';
    for (std::size_t k = 0; k < table.rows(); ++k) {
      line.clear();
      append_number(line, table.times()[k]);
      for (double v : table.row(k)) {
        line += ',';
        append_number(line, v);
      }
      out << line << '\n';
    }
  });
}

std::string summary_json(const SimulationResult& result) {
  const auto& s = result.statistics;
  nlohmann::json j = {
      {"status", std::string(to_string(result.status))},
      {"message", result.message},
      {"warnings", result.warnings},
      {"statistics",
       {{"steps", s.steps},
        {"rhs_evaluations", s.rhs_evaluations},
        {"jacobian_evaluations", s.jacobian_evaluations},
        {"sensitivity_rhs_evaluations", s.sensitivity_rhs_evaluations},
        {"error_test_failures", s.error_test_failures},
        {"nonlinear_convergence_failures", s.nonlinear_convergence_failures},
        {"events", s.events},
        {"restarts", s.restarts},
        {"difference_jacobians", s.difference_jacobians},
        {"linear_solver", s.sparse_linear_solver ? "klu" : "dense"}}},
      {"timings", {{"wall_time_seconds", s.wall_time_seconds}}},
      {"event_times", result.event_times},
      {"columns", result.trajectory.names()},
      {"rows", result.trajectory.rows()},
      {"sensitivity_parameters", result.sensitivity_parameters},
  };
  return j.dump(2) + "\n";
}

void write_summary_json(const std::string& path, const SimulationResult& result) {
  std::string text = summary_json(result);
  write_file_atomic(path, [&](std::ostream& out) { out << text; });
}

}  // namespace mo::runtime
