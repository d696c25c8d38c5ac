// A maximum matching that prefers low-cost edges: edges are admitted tier by
// tier (ascending cost) and each tier only augments the matching of the
// tiers before, so the matched rows of a cheaper tier stay matched. Used by
// dummy-derivative selection: the cheaper an edge (equation, variable), the
// more the variable should become a dummy rather than stay a state.
#pragma once

#include <vector>

namespace mo::symbolic::detail {

/// An edge of row `row` to column `col` with cost `cost`.
struct CostEdge {
  int col;
  int cost;
};

/// For each row, the column matched to it (or -1). Within one tier, a row's
/// edges are tried in the order given.
std::vector<int> tiered_matching(const std::vector<std::vector<CostEdge>>& rows, int columns);

}  // namespace mo::symbolic::detail
