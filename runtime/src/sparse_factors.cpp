// Sparse LU of large linear blocks; see sparse_factors.hpp.
#include "sparse_factors.hpp"

#include <algorithm>

namespace mo::runtime::generated {

namespace {

/// The block's pattern as a compressed matrix (a repeated entry counts once,
/// the last one's value wins, as in the dense assembly), and for each entry
/// its position among the matrix's stored values.
void analyse(SparseFactors& f, const LinearBlock& block) {
  const int n = block.size;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(block.num_entries));
  for (int k = 0; k < block.num_entries; ++k)
    triplets.emplace_back(block.entries[k].row, block.entries[k].col, 1.0);
  f.matrix.resize(n, n);
  f.matrix.setFromTriplets(triplets.begin(), triplets.end());
  f.matrix.makeCompressed();
  f.position.resize(static_cast<std::size_t>(block.num_entries));
  for (int k = 0; k < block.num_entries; ++k) {
    const BlockEntry& e = block.entries[k];
    const int* begin = f.matrix.innerIndexPtr() + f.matrix.outerIndexPtr()[e.col];
    const int* end = f.matrix.innerIndexPtr() + f.matrix.outerIndexPtr()[e.col + 1];
    f.position[static_cast<std::size_t>(k)] = static_cast<int>(std::lower_bound(begin, end, e.row) -
                                                               f.matrix.innerIndexPtr());
  }
  f.lu.analyzePattern(f.matrix);
  f.pattern = block.entries;
  f.pattern_size = block.num_entries;
  f.factored.clear();
}

}  // namespace

std::string solve_sparse(SparseFactors& f, const LinearBlock& block) {
  if (f.pattern != block.entries || f.pattern_size != block.num_entries) analyse(f, block);
  if (f.values != f.factored) {
    f.factored.clear();
    double* stored = f.matrix.valuePtr();
    std::fill(stored, stored + f.matrix.nonZeros(), 0.0);
    for (std::size_t k = 0; k < f.values.size(); ++k) stored[f.position[k]] = f.values[k];
    f.lu.factorize(f.matrix);
    if (f.lu.info() != Eigen::Success) return "the matrix is singular";
    f.factored = f.values;
  }
  Eigen::Map<Eigen::VectorXd> rhs(f.rhs.data(), static_cast<Eigen::Index>(f.rhs.size()));
  Eigen::VectorXd z = f.lu.solve(rhs);
  if (f.lu.info() != Eigen::Success || !z.allFinite()) return "the matrix is singular";
  rhs = z;
  return {};
}

SparseFactorCache::SparseFactorCache() = default;
SparseFactorCache::~SparseFactorCache() = default;
SparseFactorCache::SparseFactorCache(const SparseFactorCache&) {}
SparseFactorCache& SparseFactorCache::operator=(const SparseFactorCache& other) {
  if (this != &other) blocks_.clear();
  return *this;
}

SparseFactors& SparseFactorCache::of(const LinearBlock& block) {
  std::unique_ptr<SparseFactors>& f = blocks_[&block];
  if (!f) f = std::make_unique<SparseFactors>();
  return *f;
}

}  // namespace mo::runtime::generated
