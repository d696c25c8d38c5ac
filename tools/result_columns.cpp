// Columns and rows of result files; see result_columns.hpp.
#include "result_columns.hpp"

#include <cmath>
#include <unordered_set>

namespace mo::tools {

std::size_t add_all_variables(symbolic::OdeModel& ode, std::size_t algebraics) {
  std::unordered_set<std::string> taken;
  for (const auto& x : ode.states) taken.insert(x.info.name);
  for (const auto& y : ode.outputs) taken.insert(y.info.name);
  std::vector<symbolic::OdeOutput> added;
  for (std::size_t i = 0; i < algebraics && i < ode.algebraics.size(); ++i)
    if (taken.insert(ode.algebraics[i].info.name).second)
      added.push_back({ode.algebraics[i].info, ode.algebraics[i].symbol});
  for (const auto& e : ode.eliminated)
    if (taken.insert(e.info.name).second) added.push_back(e);
  for (const auto& d : ode.discrete)  // not the flags of initial() and sample()
    if (d.info.name.find('(') == std::string::npos && taken.insert(d.info.name).second)
      added.push_back({d.info, d.symbol});
  ode.outputs.insert(ode.outputs.end(), added.begin(), added.end());
  return added.size();
}

runtime::ResultTable select_columns(const runtime::ResultTable& table, const std::optional<std::regex>& filter) {
  if (!filter) return table;
  std::vector<std::size_t> keep;
  std::vector<std::string> names;
  for (std::size_t j = 0; j < table.names().size(); ++j)
    if (std::regex_match(table.names()[j], *filter)) {
      keep.push_back(j);
      names.push_back(table.names()[j]);
    }
  runtime::ResultTable out(std::move(names));
  std::vector<double> row(keep.size());
  for (std::size_t k = 0; k < table.rows(); ++k) {
    for (std::size_t i = 0; i < keep.size(); ++i) row[i] = table.at(k, keep[i]);
    out.add_row(table.times()[k], row);
  }
  return out;
}

std::optional<std::size_t> first_non_finite_row(const runtime::ResultTable& table) {
  for (std::size_t k = 0; k < table.rows(); ++k) {
    if (!std::isfinite(table.times()[k])) return k;
    for (double v : table.row(k))
      if (!std::isfinite(v)) return k;
  }
  return std::nullopt;
}

std::string non_finite_columns(const runtime::ResultTable& table, std::size_t k, std::size_t limit) {
  std::string out;
  std::size_t count = 0;
  for (std::size_t j = 0; j < table.names().size(); ++j) {
    if (std::isfinite(table.at(k, j))) continue;
    if (count++ == limit) return out + ", ...";
    out += (out.empty() ? "" : ", ") + table.names()[j];
  }
  return out;
}

runtime::ResultTable first_rows(const runtime::ResultTable& table, std::size_t end) {
  runtime::ResultTable out(table.names());
  for (std::size_t k = 0; k < end && k < table.rows(); ++k) out.add_row(table.times()[k], table.row(k));
  return out;
}

}  // namespace mo::tools
