// The linear-block driver of generated code (generated_support.hpp): dense LU
// below kSparseBlockSize unknowns, sparse LU from there on. Both solve a
// tridiagonal system, refactorise when its values change, and report a
// singular or non-finite block with its description.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "mo/runtime/generated_support.hpp"

using namespace mo::runtime::generated;

namespace {

/// J z = -c with J tridiagonal (diagonal d, off-diagonals -1) in work slots:
/// w[0 .. n) the unknowns, w[n .. 2n) c, then the entries' values.
struct Tridiagonal {
  int n;
  std::vector<int> unknowns, offsets;
  std::vector<BlockEntry> entries;
  std::vector<double> w;
  LinearBlock block() const {
    return {n, unknowns.data(), offsets.data(), entries.data(), static_cast<int>(entries.size()),
            "test block"};
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
