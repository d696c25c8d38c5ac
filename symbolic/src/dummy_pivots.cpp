// Numeric checks of dummy-derivative selection; see dummy_pivots.hpp.
#include "dummy_pivots.hpp"

#include <algorithm>
#include <cmath>

namespace mo::symbolic::detail {

namespace {

constexpr double kTolerance = 1e-9;

double max_abs(const std::vector<double>& row) {
  double m = 0.0;
  for (double x : row) m = std::max(m, std::fabs(x));
  return m;
}

/// row −= (row[col] / pivot[col]) · pivot.
void eliminate(std::vector<double>& row, const std::vector<double>& pivot, std::size_t col) {
  const double f = row[col] / pivot[col];
  if (f == 0.0) return;
  for (std::size_t c = 0; c < row.size(); ++c) row[c] -= f * pivot[c];
  row[col] = 0.0;
}

}  // namespace

bool regular_choice(const DenseJacobian& jac, const std::vector<int>& chosen) {
  std::vector<std::vector<double>> block;
  std::vector<std::size_t> cols;
  for (std::size_t r = 0; r < chosen.size(); ++r)
    if (chosen[r] >= 0) cols.push_back(static_cast<std::size_t>(chosen[r]));
  for (std::size_t r = 0; r < chosen.size(); ++r) {
    if (chosen[r] < 0) continue;
    std::vector<double> row;
    for (std::size_t c : cols) row.push_back(jac[r][c]);
    block.push_back(std::move(row));
  }
  // Gaussian elimination with partial pivoting, column by column.
  const std::size_t n = block.size();
  std::vector<double> scale(n);
  for (std::size_t r = 0; r < n; ++r) scale[r] = max_abs(block[r]);
  for (std::size_t k = 0; k < n; ++k) {
    std::size_t p = k;
    for (std::size_t r = k + 1; r < n; ++r)
      if (std::fabs(block[r][k]) > std::fabs(block[p][k])) p = r;
    std::swap(block[k], block[p]);
    std::swap(scale[k], scale[p]);
    if (!(std::fabs(block[k][k]) > kTolerance * scale[k])) return false;
    for (std::size_t r = k + 1; r < n; ++r) eliminate(block[r], block[k], k);
  }
  return true;
}

std::optional<std::vector<int>> regular_columns(const DenseJacobian& jac,
                                                const std::vector<int>& cost) {
  std::vector<std::vector<double>> pivots;
  std::vector<std::size_t> pivot_cols;
  std::vector<int> out;
  for (const auto& original : jac) {
    std::vector<double> row = original;
    const double scale = max_abs(row);
    for (std::size_t k = 0; k < pivots.size(); ++k) eliminate(row, pivots[k], pivot_cols[k]);
    int best = -1;
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (!(std::fabs(row[c]) > kTolerance * scale)) continue;
      const auto b = static_cast<std::size_t>(best);
      if (best < 0 || cost[c] < cost[b] || (cost[c] == cost[b] && std::fabs(row[c]) > std::fabs(row[b])))
        best = static_cast<int>(c);
    }
    if (best < 0) return std::nullopt;
    out.push_back(best);
    pivots.push_back(std::move(row));
    pivot_cols.push_back(static_cast<std::size_t>(best));
  }
  return out;
}

}  // namespace mo::symbolic::detail
