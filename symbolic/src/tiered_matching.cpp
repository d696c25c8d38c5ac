// Tiered maximum matching; see tiered_matching.hpp.
#include "tiered_matching.hpp"

#include <algorithm>
#include <deque>
#include <set>

namespace mo::symbolic::detail {

namespace {

/// Augments from the unmatched row `r` by breadth-first search over edges of
/// cost <= `tier` (no recursion). Returns true if r became matched.
bool augment(const std::vector<std::vector<CostEdge>>& rows, int r, int tier, std::vector<int>& col_of,
             std::vector<int>& row_of) {
  std::vector<int> reached_from(row_of.size(), -2);  // column → row that reached it
  std::deque<int> queue{r};
  while (!queue.empty()) {
    const int row = queue.front();
    queue.pop_front();
    for (const CostEdge& e : rows[static_cast<std::size_t>(row)]) {
      const auto c = static_cast<std::size_t>(e.col);
      if (e.cost > tier || reached_from[c] != -2) continue;
      reached_from[c] = row;
      if (row_of[c] >= 0) {
        queue.push_back(row_of[c]);
        continue;
      }
      for (int col = e.col; col >= 0;) {  // flip the path back to r
        const int from = reached_from[static_cast<std::size_t>(col)];
        const int previous = col_of[static_cast<std::size_t>(from)];
        col_of[static_cast<std::size_t>(from)] = col;
        row_of[static_cast<std::size_t>(col)] = from;
        col = previous;
      }
      return true;
    }
  }
  return false;
}

}  // namespace

std::vector<int> tiered_matching(const std::vector<std::vector<CostEdge>>& rows, int columns) {
  std::set<int> tiers;
  for (const auto& row : rows)
    for (const CostEdge& e : row) tiers.insert(e.cost);
  std::vector<int> col_of(rows.size(), -1), row_of(static_cast<std::size_t>(columns), -1);
  for (int tier : tiers)
    for (std::size_t r = 0; r < rows.size(); ++r)
      if (col_of[r] < 0) augment(rows, static_cast<int>(r), tier, col_of, row_of);
  return col_of;
}

}  // namespace mo::symbolic::detail
