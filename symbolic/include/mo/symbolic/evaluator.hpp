// Numerical evaluation of a set of output expressions at given values of the
// leaves (symbols, der(x), pre(x)). The graph is lowered once to a flat list
// of instructions in topological order, each writing one work slot, so that
// shared subexpressions are computed once. Booleans evaluate to 0 and 1.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "mo/symbolic/expr_arena.hpp"

namespace mo::symbolic {

/// Values of leaves by handle, for the one-shot evaluate().
using LeafValues = std::unordered_map<Expr, double, ExprHash>;

/// Outputs lowered to instructions; reusable for many leaf values. Holds no
/// reference to the arena, so the arena may grow or go away afterwards.
class Evaluator {
public:
  /// Lowers `outputs`. Throws std::out_of_range for a bad handle.
  Evaluator(const ExprArena& arena, std::span<const Expr> outputs);

  /// The leaves the outputs depend on, ascending id: the order in which
  /// evaluate() expects their values.
  const std::vector<Expr>& leaves() const { return leaves_; }
  /// Number of outputs.
  std::size_t output_count() const { return outputs_.size(); }
  /// Number of instructions (distinct nodes) executed per evaluation.
  std::size_t instruction_count() const { return instructions_.size(); }

  /// Output values for `leaf_values` (parallel to leaves()). Throws
  /// std::invalid_argument if the sizes differ. NaN and Inf propagate.
  std::vector<double> evaluate(std::span<const double> leaf_values) const;
  /// As above into `outputs`, using `work` (resized as needed) as scratch.
  void evaluate(std::span<const double> leaf_values, std::span<double> outputs,
                std::vector<double>& work) const;

private:
  struct Instruction {
    ExprKind kind;
    std::uint32_t operand[3]; // work slots; for Constant, index into constants_
  };
  std::vector<Instruction> instructions_; // slot i is written by instruction i
  std::vector<double> constants_;
  std::vector<Expr> leaves_;
  std::vector<std::uint32_t> leaf_slots_;   // parallel to leaves_
  std::vector<std::uint32_t> outputs_;      // slot of each output
  std::vector<std::vector<std::uint32_t>> lists_;  // External: the slots of its arguments
};

/// Values of `outputs` with leaves looked up in `values`. Throws
/// std::invalid_argument naming the first leaf that has no value.
std::vector<double> evaluate(const ExprArena& arena, std::span<const Expr> outputs,
                             const LeafValues& values);

} // namespace mo::symbolic
