// Any variable as a measured output; see measured_outputs.hpp.
#include "measured_outputs.hpp"

#include "mo/runtime/mat_file.hpp"

#include <fstream>
#include <optional>
#include <sstream>

namespace mo::tools {

namespace {

/// The value of the variable called `name` in `m`, with its declared info.
std::optional<symbolic::OdeOutput> variable_value(const symbolic::OdeModel& m,
                                                  const std::string& name) {
  for (const auto& x : m.states)
    if (x.info.name == name) return symbolic::OdeOutput{x.info, x.symbol};
  for (const auto& a : m.algebraics)
    if (a.info.name == name) return symbolic::OdeOutput{a.info, a.symbol};
  for (const auto& e : m.eliminated)
    if (e.info.name == name) return e;
  for (const auto& u : m.inputs)
    if (u.info.name == name) return symbolic::OdeOutput{u.info, u.symbol};
  for (const auto& p : m.parameters)
    if (p.info.name == name) return symbolic::OdeOutput{p.info, p.symbol};
  return std::nullopt;
}

}  // namespace

std::vector<std::string> add_measured_outputs(symbolic::OdeModel& model,
                                              const std::vector<std::string>& names) {
  std::vector<std::string> unknown;
  for (const std::string& name : names) {
    bool exists = false;
    for (const auto& y : model.outputs) exists = exists || y.info.name == name;
    if (exists) continue;
    if (auto y = variable_value(model, name))
      model.outputs.push_back(std::move(*y));
    else
      unknown.push_back(name);
  }
  return unknown;
}

std::vector<std::string> csv_columns(const std::string& path) {
  if (runtime::is_mat_file(path)) return {};  // its measured columns are named by `outputs`
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> out;
    std::stringstream ss(line);
    std::string field;
    for (bool first = true; std::getline(ss, field, ','); first = false)
      if (!first) out.push_back(field);
    return out;
  }
  return {};
}

}  // namespace mo::tools
