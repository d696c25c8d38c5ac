// The products a generated Hessian runs for the columns an evaluation wants
// (plan_hessian, generated_support.hpp), on tables written by hand as the
// code generator prints them.
#include <catch2/catch.hpp>

#include <map>
#include <set>
#include <utility>
#include <vector>

#include "mo/runtime/generated_support.hpp"

using namespace mo::runtime::generated;

namespace {

/// Columns z = (x0, x1, p0, p1). Row 0's second derivative involves x0 and
/// p0: T0(x0, x0), T0(p0, x0), T0(p0, p0); row 1's x0, x1 and p1: T1(x1, x0),
/// T1(p1, x1). All four columns are coloured x0 → 0, x1 → 1, p0 → 1, p1 → 2.
/// Lower-triangle positions: (0,0) 0, (1,0) 1, (2,0) 2, (3,1) 3, (2,2) 4.
struct Tables {
  std::vector<int> col_start{0, 3, 4, 5, 5}, row_index{0, 1, 2, 3, 2};
  std::vector<int> colour_start{0, 1, 3, 4}, colour_columns{0, 1, 2, 3};
  std::vector<int> sigma{0, 0, 1, 1}, tau{0, 1, 1, 2};
  std::vector<int> entry_start{0, 1, 3, 4, 5};
  std::vector<int> entry_weight{0, 0, 1, 0, 1}, entry_slot{10, 10, 11, 10, 11}, entry_index{0, 2, 1, 4, 3};

  HessianTablesView view() const {
    return {4,          col_start.data(),   row_index.data(),   colour_start.data(),
            colour_columns.data(), sigma.size(), sigma.data(), tau.data(),
            entry_start.data(),    entry_weight.data(), entry_slot.data(), entry_index.data()};
  }
};

/// (row weight, pattern position) of every entry, and checks that no product
/// holds two entries of one row and no row has two columns of one colour.
std::set<std::pair<int, int>> entries_of(const HessianPlan& plan, const Tables& t) {
  std::map<int, int> colour;
  for (std::size_t k = 0; k + 1 < plan.colour_start.size(); ++k)
    for (int c = plan.colour_start[k]; c < plan.colour_start[k + 1]; ++c) {
      CHECK(colour.count(plan.colour_columns[std::size_t(c)]) == 0);
      colour[plan.colour_columns[std::size_t(c)]] = static_cast<int>(k);
    }
  std::map<int, std::map<int, int>> row_colour_column;  // row → colour → column
  std::set<std::pair<int, int>> out;
  for (std::size_t q = 0; q < plan.products(); ++q) {
    CHECK(plan.sigma[q] <= plan.tau[q]);
    if (q > 0) CHECK(std::pair{plan.sigma[q - 1], plan.tau[q - 1]} < std::pair{plan.sigma[q], plan.tau[q]});
    std::set<int> rows;
    for (int e = plan.entry_start[q]; e < plan.entry_start[q + 1]; ++e) {
      const int i = plan.entry_weight[std::size_t(e)], k = plan.entry_index[std::size_t(e)];
      CHECK(rows.insert(i).second);
      CHECK(plan.entry_slot[std::size_t(e)] == 10 + i);
      CHECK(out.insert({i, k}).second);
      int c = 0;
      while (t.col_start[std::size_t(c) + 1] <= k) ++c;
      const int r = t.row_index[std::size_t(k)];
      CHECK(std::set{colour.at(r), colour.at(c)} == std::set{plan.sigma[q], plan.tau[q]});
      for (int z : {r, c}) {
        auto [it, fresh] = row_colour_column[i].insert({colour.at(z), z});
        CHECK(it->second == z);
      }
    }
  }
  return out;
}

}  // namespace

TEST_CASE("Hessian plan: every column wanted gives the printed products", "[hessian]") {
  const Tables t;
  HessianPlan plan;
  plan_hessian(t.view(), {}, plan);
  CHECK(plan.colour_start == t.colour_start);
  CHECK(plan.colour_columns == t.colour_columns);
  CHECK(plan.sigma == t.sigma);
  CHECK(plan.tau == t.tau);
  CHECK(plan.entry_start == t.entry_start);
  CHECK(plan.entry_weight == t.entry_weight);
  CHECK(plan.entry_slot == t.entry_slot);
  CHECK(plan.entry_index == t.entry_index);
  CHECK(entries_of(plan, t) == std::set<std::pair<int, int>>{{0, 0}, {0, 2}, {0, 4}, {1, 1}, {1, 3}});
}

TEST_CASE("Hessian plan: the states alone are coloured again, in fewer products", "[hessian]") {
  const Tables t;
  HessianPlan plan;
  plan_hessian(t.view(), std::vector<std::uint8_t>{1, 1, 0, 0}, plan);
  // x0 and x1 share row 1: two colours; T0(x0, x0) and T1(x1, x0) in two products (of four).
  CHECK(plan.colour_start == std::vector<int>{0, 1, 2});
  CHECK(plan.colour_columns == std::vector<int>{0, 1});
  CHECK(plan.products() == 2);
  CHECK(entries_of(plan, t) == std::set<std::pair<int, int>>{{0, 0}, {1, 1}});
}

TEST_CASE("Hessian plan: columns of different rows share a colour", "[hessian]") {
  const Tables t;
  HessianPlan plan;
  plan_hessian(t.view(), std::vector<std::uint8_t>{0, 1, 1, 1}, plan);
  // Wanted entries: T0(p0, p0) and T1(p1, x1). p0 (row 0 only) takes colour 0
  // after x1 took it: x1 → 0, p0 → 0, p1 → 1.
  CHECK(plan.colour_columns == std::vector<int>{1, 2, 3});
  CHECK(plan.colour_start == std::vector<int>{0, 2, 3});
  CHECK(plan.products() == 2);
  CHECK(entries_of(plan, t) == std::set<std::pair<int, int>>{{0, 4}, {1, 3}});
}

TEST_CASE("Hessian plan: no wanted entry, no product", "[hessian]") {
  const Tables t;
  HessianPlan plan;
  plan_hessian(t.view(), std::vector<std::uint8_t>{0, 0, 0, 1}, plan);
  CHECK(plan.products() == 0);
  CHECK(plan.entry_start == std::vector<int>{0});
  CHECK(plan.colour_start == std::vector<int>{0});
}
