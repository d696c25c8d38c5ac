// The linear-block driver of generated code (generated_support.hpp): dense LU
// below kSparseBlockSize unknowns, sparse LU from there on. Both solve a
// tridiagonal system, refactorise when its values change, take the
// minimum-norm solution of a singular block whose equations are consistent,
// and report a contradicting or non-finite block with its description.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "mo/runtime/generated_support.hpp"
#include "mo/runtime/linear_solve.hpp"

using namespace mo::runtime::generated;

namespace {

/// J z = -c with J tridiagonal (diagonal d, off-diagonals -1) in work slots:
/// w[0 .. n) the unknowns, w[n .. 2n) c, then the entries' values.
struct Tridiagonal {
  int n;
  std::vector<int> unknowns, offsets;
  std::vector<BlockEntry> entries;
  std::vector<double> w;
  LinearBlock block(const char* description = "test block") const {
    return {n, unknowns.data(), offsets.data(), entries.data(), static_cast<int>(entries.size()), description};
  }
  explicit Tridiagonal(int size) : n(size) {
    for (int i = 0; i < n; ++i) unknowns.push_back(i), offsets.push_back(n + i);
    int slot = 2 * n;
    for (int i = 0; i < n; ++i)
      for (int j = std::max(0, i - 1); j <= std::min(n - 1, i + 1); ++j) entries.push_back({i, j, slot++});
    w.assign(static_cast<std::size_t>(slot), 0.0);
  }
  /// Diagonal d, and c such that z = (1, 2, ..., n).
  void set(double d) {
    for (const BlockEntry& e : entries) w[std::size_t(e.slot)] = e.row == e.col ? d : -1.0;
    for (int i = 0; i < n; ++i) {
      double jz = d * (i + 1);
      if (i > 0) jz -= i;
      if (i + 1 < n) jz -= i + 2;
      w[std::size_t(n + i)] = -jz;
    }
  }
  /// Column k of J set to 0, and c such that z = (1, 2, ..., n) but for z_k,
  /// which no equation then determines.
  void drop_column(int k) {
    for (const BlockEntry& e : entries)
      if (e.col == k) {
        w[std::size_t(n + e.row)] += w[std::size_t(e.slot)] * (k + 1);  // c = -J z without column k
        w[std::size_t(e.slot)] = 0.0;
      }
  }
};

}  // namespace

TEST_CASE("linear blocks: dense and sparse LU solve, refactorise and report", "[blocks]") {
  for (int n : {3, kSparseBlockSize - 1, kSparseBlockSize, 200}) {
    INFO("n = " << n);
    Tridiagonal t(n);
    BlockWorkspace ws;
    const LinearBlock b = t.block();
    for (double d : {4.0, 2.5, 2.5, 3.0}) {  // a repeated matrix reuses its factors
      t.set(d);
      REQUIRE(solve_linear(b, t.w.data(), ws));
      for (int i = 0; i < n; ++i) CHECK(t.w[std::size_t(i)] == Approx(i + 1).epsilon(1e-12));
    }
    // A zero column: singular, the unknowns NaN, the block named.
    for (const BlockEntry& e : t.entries)
      if (e.col == n / 2) t.w[std::size_t(e.slot)] = 0.0;
    CHECK_FALSE(solve_linear(b, t.w.data(), ws));
    CHECK(std::isnan(t.w[0]));
    CHECK(ws.failure.find("test block") == 0);
    CHECK(ws.failure.find("singular") != std::string::npos);
    // A NaN coefficient is reported as such.
    ws.failure.clear();
    t.set(4.0);
    t.w[std::size_t(t.entries[0].slot)] = std::nan("");
    CHECK_FALSE(solve_linear(b, t.w.data(), ws));
    CHECK(ws.failure.find("not finite") != std::string::npos);
    // A copy of the workspace (a cloned model) solves on its own.
    ws.failure.clear();
    t.set(3.0);
    BlockWorkspace copy = ws;
    REQUIRE(solve_linear(b, t.w.data(), copy));
    CHECK(t.w[std::size_t(n - 1)] == Approx(n).epsilon(1e-12));
  }
}

TEST_CASE("linear blocks: a singular block with consistent equations gets its minimum-norm solution", "[blocks]") {
  for (int n : {3, kSparseBlockSize - 1, kSparseBlockSize, 200}) {
    INFO("n = " << n);
    Tridiagonal t(n);
    BlockWorkspace ws;
    ws.time = 0.25;
    const LinearBlock b = t.block("linear block 1 for z\n  equations: here");
    for (int repeat = 0; repeat < 2; ++repeat) {
      t.set(3.0);
      t.drop_column(n / 2);
      REQUIRE(solve_linear(b, t.w.data(), ws));
      for (int i = 0; i < n; ++i) CHECK(t.w[std::size_t(i)] == Approx(i == n / 2 ? 0 : i + 1).margin(1e-10));
    }
    REQUIRE(ws.singular.size() == 1);
    CHECK(ws.singular[0].count == 2);
    CHECK(singular_notes(ws) == std::vector<std::string>{
                                    "linear block 1 for z was singular in 2 solves, the earliest at t = 0.25: its equations "
                                    "leave part of it undetermined, and their minimum-norm solution was taken"});
    // The same block solved again after the matrix is regular: LU, no new count.
    t.set(3.0);
    REQUIRE(solve_linear(b, t.w.data(), ws));
    CHECK(t.w[std::size_t(n / 2)] == Approx(n / 2 + 1).epsilon(1e-12));
    CHECK(ws.singular[0].count == 2);
    // Equations that contradict each other: without column n/2, J z = -c has
    // no solution once row n/2's c moves (J's left null vector is A⁻ᵀ e_k
    // of the full matrix, nonzero in row k).
    t.drop_column(n / 2);
    t.w[std::size_t(n + n / 2)] += 1.0;
    CHECK_FALSE(solve_linear(b, t.w.data(), ws));
    CHECK(std::isnan(t.w[0]));
    CHECK(ws.failure.find("the matrix is singular and its equations contradict each other") != std::string::npos);
  }
}

TEST_CASE("solve_minimum_norm: least norm among the solutions, none for contradicting equations", "[blocks]") {
  using mo::runtime::solve_minimum_norm;
  // x + y = 2 twice: x = y = 1 has the least norm.
  std::vector<double> b{2, 2};
  REQUIRE(solve_minimum_norm(std::vector<double>{1, 1, 1, 1}, b));
  CHECK(b[0] == Approx(1).epsilon(1e-14));
  CHECK(b[1] == Approx(1).epsilon(1e-14));
  // x + y = 2, x + y = 3: no solution, b unchanged.
  b = {2, 3};
  CHECK_FALSE(solve_minimum_norm(std::vector<double>{1, 1, 1, 1}, b));
  CHECK(b == std::vector<double>{2, 3});
  // A zero matrix: z = 0 for b = 0, nothing otherwise.
  b = {0, 0};
  REQUIRE(solve_minimum_norm(std::vector<double>(4, 0.0), b));
  CHECK(b == std::vector<double>{0, 0});
  b = {0, 1e-300};
  CHECK_FALSE(solve_minimum_norm(std::vector<double>(4, 0.0), b));
  // Not finite: refused.
  b = {1, std::nan("")};
  CHECK_FALSE(solve_minimum_norm(std::vector<double>{1, 0, 0, 1}, b));
}
