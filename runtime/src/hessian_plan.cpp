// The products of a generated Hessian for the columns an evaluation wants;
// see plan_hessian in generated_support.hpp.
#include <algorithm>

#include "mo/runtime/generated_support.hpp"

namespace mo::runtime::generated {

namespace {

/// One tensor entry T_i(r, c) of a row, where the tables put it.
struct Entry {
  int weight, slot, index;
  int row, column;  // its pattern position's row and column
};

/// The tables as printed (every column wanted).
void copy_tables(const HessianTablesView& h, HessianPlan& out) {
  std::size_t count = 0;  // colours up to the last one a product seeds
  for (std::size_t q = 0; q < h.products; ++q) count = std::max(count, static_cast<std::size_t>(h.tau[q]) + 1);
  out.colour_start.assign(h.colour_start, h.colour_start + count + 1);
  out.colour_columns.assign(h.colour_columns, h.colour_columns + h.colour_start[count]);
  out.sigma.assign(h.sigma, h.sigma + h.products);
  out.tau.assign(h.tau, h.tau + h.products);
  const int entries = h.entry_start[h.products];
  out.entry_start.assign(h.entry_start, h.entry_start + h.products + 1);
  out.entry_weight.assign(h.entry_weight, h.entry_weight + entries);
  out.entry_slot.assign(h.entry_slot, h.entry_slot + entries);
  out.entry_index.assign(h.entry_index, h.entry_index + entries);
}

/// The entries whose row and column are both wanted.
std::vector<Entry> wanted_entries(const HessianTablesView& h, std::span<const std::uint8_t> columns) {
  std::vector<int> column_of(static_cast<std::size_t>(h.col_start[h.n]));  // of each pattern position
  for (int c = 0; c < h.n; ++c)
    for (int k = h.col_start[c]; k < h.col_start[c + 1]; ++k) column_of[static_cast<std::size_t>(k)] = c;
  auto wanted = [&](int column) {
    const auto c = static_cast<std::size_t>(column);
    return c < columns.size() && columns[c] != 0;
  };
  std::vector<Entry> out;
  for (int e = 0; e < h.entry_start[h.products]; ++e) {
    const int k = h.entry_index[e];
    const int r = h.row_index[k], c = column_of[static_cast<std::size_t>(k)];
    if (wanted(r) && wanted(c)) out.push_back({h.entry_weight[e], h.entry_slot[e], k, r, c});
  }
  return out;
}

/// Greedy colours of the columns the entries involve: two columns of one row
/// (weight) differ. -1 for a column no entry involves.
std::vector<int> colour_columns(int n, const std::vector<Entry>& entries, int& colours) {
  int rows = 0;
  for (const Entry& e : entries) rows = std::max(rows, e.weight + 1);
  std::vector<std::vector<int>> of_row(static_cast<std::size_t>(rows)), of_column(static_cast<std::size_t>(n));
  for (const Entry& e : entries)
    for (int c : {e.row, e.column}) {
      of_row[static_cast<std::size_t>(e.weight)].push_back(c);
      of_column[static_cast<std::size_t>(c)].push_back(e.weight);
    }
  for (auto* lists : {&of_row, &of_column})
    for (auto& l : *lists) {
      std::sort(l.begin(), l.end());
      l.erase(std::unique(l.begin(), l.end()), l.end());
    }
  std::vector<int> colour(static_cast<std::size_t>(n), -1), taken;  // taken[k] == c: colour k is c's neighbour's
  colours = 0;
  for (int c = 0; c < n; ++c) {
    if (of_column[static_cast<std::size_t>(c)].empty()) continue;
    for (int i : of_column[static_cast<std::size_t>(c)])
      for (int other : of_row[static_cast<std::size_t>(i)])
        if (const int k = colour[static_cast<std::size_t>(other)]; k >= 0) taken[static_cast<std::size_t>(k)] = c;
    int k = 0;
    while (k < colours && taken[static_cast<std::size_t>(k)] == c) ++k;
    if (k == colours) ++colours, taken.push_back(-1);
    colour[static_cast<std::size_t>(c)] = k;
  }
  return colour;
}

}  // namespace

void plan_hessian(const HessianTablesView& h, std::span<const std::uint8_t> columns, HessianPlan& out) {
  out = HessianPlan{};
  if (columns.empty()) return copy_tables(h, out);
  std::vector<Entry> entries = wanted_entries(h, columns);
  int colours = 0;
  const std::vector<int> colour = colour_columns(h.n, entries, colours);
  for (int k = 0; k < colours; ++k) {
    for (int c = 0; c < h.n; ++c)
      if (colour[static_cast<std::size_t>(c)] == k) out.colour_columns.push_back(c);
    out.colour_start.push_back(static_cast<int>(out.colour_columns.size()));
  }
  auto key = [&](const Entry& e) {
    const int a = colour[static_cast<std::size_t>(e.row)], b = colour[static_cast<std::size_t>(e.column)];
    return std::pair{std::min(a, b), std::max(a, b)};
  };
  std::stable_sort(entries.begin(), entries.end(), [&](const Entry& x, const Entry& y) { return key(x) < key(y); });
  for (std::size_t e = 0; e < entries.size(); ++e) {
    const auto [sigma, tau] = key(entries[e]);
    if (e == 0 || key(entries[e - 1]) != std::pair{sigma, tau}) {
      if (e > 0) out.entry_start.push_back(static_cast<int>(e));
      out.sigma.push_back(sigma);
      out.tau.push_back(tau);
    }
    out.entry_weight.push_back(entries[e].weight);
    out.entry_slot.push_back(entries[e].slot);
    out.entry_index.push_back(entries[e].index);
  }
  if (!entries.empty()) out.entry_start.push_back(static_cast<int>(entries.size()));
}

}  // namespace mo::runtime::generated
