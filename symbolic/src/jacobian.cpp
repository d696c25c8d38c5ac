#include "mo/symbolic/jacobian.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic {

bool SparsityPattern::contains(std::size_t row, std::size_t column) const {
  if (row >= rows) throw std::out_of_range("SparsityPattern::contains(): row out of range");
  const auto begin = col.begin() + static_cast<std::ptrdiff_t>(row_start[row]);
  const auto end = col.begin() + static_cast<std::ptrdiff_t>(row_start[row + 1]);
  return std::binary_search(begin, end, static_cast<std::uint32_t>(column));
}

SparsityPattern jacobian_sparsity(const ExprArena& arena, std::span<const Expr> outputs,
                                  std::span<const Expr> wrt) {
  std::unordered_map<Expr, std::uint32_t, ExprHash> column_of;
  for (std::size_t j = 0; j < wrt.size(); ++j) {
    if (!arena.is_leaf(wrt[j]))
      throw std::invalid_argument("jacobian: " + to_modelica(arena, wrt[j]) +
                                  " is not a symbol, der() or pre()");
    if (!column_of.emplace(wrt[j], static_cast<std::uint32_t>(j)).second)
      throw std::invalid_argument("jacobian: " + to_modelica(arena, wrt[j]) + " appears twice");
  }
  SparsityPattern pattern;
  pattern.rows = outputs.size();
  pattern.cols = wrt.size();
  pattern.row_start.reserve(outputs.size() + 1);
  pattern.row_start.push_back(0);
  for (const Expr out : outputs) {
    const std::size_t first = pattern.col.size();
    for (const Expr leaf : leaves(arena, std::span<const Expr>(&out, 1)))
      if (const auto found = column_of.find(leaf); found != column_of.end())
        pattern.col.push_back(found->second);
    std::sort(pattern.col.begin() + static_cast<std::ptrdiff_t>(first), pattern.col.end());
    pattern.row_start.push_back(pattern.col.size());
  }
  return pattern;
}

SparseJacobian jacobian(ExprArena& arena, std::span<const Expr> outputs,
                        std::span<const Expr> wrt) {
  const SparsityPattern structure = jacobian_sparsity(arena, outputs, wrt);
  SparseJacobian result;
  result.pattern.rows = structure.rows;
  result.pattern.cols = structure.cols;
  result.pattern.row_start.push_back(0);
  std::vector<Expr> row_wrt;
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    row_wrt.clear();
    for (std::size_t k = structure.row_start[i]; k < structure.row_start[i + 1]; ++k)
      row_wrt.push_back(wrt[structure.col[k]]);
    const std::vector<Expr> row = gradient(arena, outputs[i], row_wrt);
    for (std::size_t k = 0; k < row.size(); ++k) {
      if (arena.is_constant(row[k], 0)) continue;
      result.pattern.col.push_back(structure.col[structure.row_start[i] + k]);
      result.values.push_back(row[k]);
    }
    result.pattern.row_start.push_back(result.pattern.col.size());
  }
  return result;
}

} // namespace mo::symbolic
