// Sparsity patterns and model metadata look-ups.
#include "mo/runtime/model.hpp"

#include <algorithm>
#include <stdexcept>

namespace mo::runtime {

Sparsity Sparsity::empty(int rows, int cols) {
  Sparsity s;
  s.rows = rows;
  s.cols = cols;
  s.col_start.assign(static_cast<std::size_t>(cols) + 1, 0);
  return s;
}

Sparsity Sparsity::dense(int rows, int cols) {
  Sparsity s;
  s.rows = rows;
  s.cols = cols;
  s.col_start.reserve(static_cast<std::size_t>(cols) + 1);
  s.col_start.push_back(0);
  for (int c = 0; c < cols; ++c) {
    for (int r = 0; r < rows; ++r) s.row_index.push_back(r);
    s.col_start.push_back(s.nnz());
  }
  return s;
}

Sparsity Sparsity::from_triplets(int rows, int cols,
                                 std::span<const std::pair<int, int>> entries) {
  std::vector<std::pair<int, int>> by_column;
  by_column.reserve(entries.size());
  for (auto [r, c] : entries) {
    if (r < 0 || r >= rows || c < 0 || c >= cols)
      throw std::invalid_argument("Sparsity::from_triplets: entry (" + std::to_string(r) +
                                  ", " + std::to_string(c) + ") outside " +
                                  std::to_string(rows) + " x " + std::to_string(cols));
    by_column.emplace_back(c, r);
  }
  std::sort(by_column.begin(), by_column.end());
  by_column.erase(std::unique(by_column.begin(), by_column.end()), by_column.end());
  Sparsity s = empty(rows, cols);
  for (auto [c, r] : by_column) {
    s.row_index.push_back(r);
    ++s.col_start[static_cast<std::size_t>(c) + 1];
  }
  for (int c = 0; c < cols; ++c) s.col_start[c + 1] += s.col_start[c];
  return s;
}

bool Sparsity::is_valid() const {
  if (rows < 0 || cols < 0) return false;
  if (col_start.size() != static_cast<std::size_t>(cols) + 1 || col_start.front() != 0 ||
      col_start.back() != nnz())
    return false;
  for (int c = 0; c < cols; ++c) {
    if (col_start[c] > col_start[c + 1]) return false;
    for (int k = col_start[c]; k < col_start[c + 1]; ++k) {
      if (row_index[k] < 0 || row_index[k] >= rows) return false;
      if (k > col_start[c] && row_index[k - 1] >= row_index[k]) return false;
    }
  }
  return true;
}

int Sparsity::find(int row, int col) const {
  if (col < 0 || col >= cols) return -1;
  auto first = row_index.begin() + col_start[col];
  auto last = row_index.begin() + col_start[col + 1];
  auto it = std::lower_bound(first, last, row);
  return (it != last && *it == row) ? static_cast<int>(it - row_index.begin()) : -1;
}

namespace {
template <class Vars>
std::optional<std::size_t> index_of(const Vars& vars, std::string_view name) {
  for (std::size_t i = 0; i < vars.size(); ++i)
    if (vars[i].name == name) return i;
  return std::nullopt;
}
}  // namespace

std::optional<std::size_t> ModelInfo::state_index(std::string_view n) const {
  return index_of(states, n);
}
std::optional<std::size_t> ModelInfo::input_index(std::string_view n) const {
  return index_of(inputs, n);
}
std::optional<std::size_t> ModelInfo::output_index(std::string_view n) const {
  return index_of(outputs, n);
}
std::optional<std::size_t> ModelInfo::parameter_index(std::string_view n) const {
  return index_of(parameters, n);
}

std::vector<double> ModelInfo::default_parameters() const {
  std::vector<double> p;
  p.reserve(parameters.size());
  for (const auto& par : parameters) p.push_back(par.value);
  return p;
}

std::size_t ModelInfo::num_base_states() const {
  return static_cast<std::size_t>(std::count_if(
      states.begin(), states.end(), [](const StateVariable& s) { return !s.sensitivity; }));
}

const Sparsity& Model::hessian_sparsity(Hessian which) const {
  (void)which;
  throw std::logic_error("internal error: Model::hessian_sparsity called on model '" +
                         info().name + "', which does not provide Hessians");
}

void Model::hessian_values(Hessian which, double, std::span<const double>,
                           std::span<const double>, std::span<const double>,
                           std::span<const double>, std::span<double>) {
  (void)which;
  throw std::logic_error("internal error: Model::hessian_values called on model '" +
                         info().name + "', which does not provide Hessians");
}

}  // namespace mo::runtime

namespace mo::runtime {

void Model::rhs_at_event(double t, std::span<const double> x, std::span<const double> u,
                         std::span<const double> p, std::span<const int>,
                         std::span<double> xdot) {
  rhs(t, x, u, p, xdot);
}

void Model::event_indicator_tangent(double, std::span<const double>, std::span<const double>,
                                    std::span<const double>, std::span<const int>,
                                    const EventTangent&, std::span<double>) {
  throw std::logic_error("internal error: Model::event_indicator_tangent called on model '" +
                         info().name + "', which does not provide event tangents");
}

EventResponse Model::handle_event_tangent(const EventCause&, std::span<double>,
                                          std::span<const double>, std::span<const double>,
                                          std::span<EventTangent>, std::string&) {
  throw std::logic_error("internal error: Model::handle_event_tangent called on model '" +
                         info().name + "', which does not provide event tangents");
}

}  // namespace mo::runtime
