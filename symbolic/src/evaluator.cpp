#include "mo/symbolic/evaluator.hpp"

#include <stdexcept>
#include <string>

#include "mo/runtime/modelica_random.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/traversal.hpp"
#include "node_set.hpp"
#include "scalar_ops.hpp"

namespace mo::symbolic {

Evaluator::Evaluator(const ExprArena& arena, std::span<const Expr> outputs) {
  // der(x) and pre(x) are leaves: their Symbol operand is not evaluated.
  const std::vector<Expr> order = topological_order(arena, outputs);
  const detail::OrderIndex index(order);
  instructions_.reserve(order.size());
  for (const Expr e : order) {
    Instruction ins{arena.kind(e), {0, 0, 0}};
    if (ins.kind == ExprKind::Constant) {
      ins.operand[0] = static_cast<std::uint32_t>(constants_.size());
      constants_.push_back(arena.constant_value(e));
    } else if (arena.is_leaf(e)) {
      leaves_.push_back(e);
      leaf_slots_.push_back(static_cast<std::uint32_t>(instructions_.size()));
    } else {
      for (std::size_t i = 0; i < arity(ins.kind); ++i)
        ins.operand[i] = static_cast<std::uint32_t>(index.position(arena.operand(e, i)));
      if (ins.kind == ExprKind::External) {  // operand 1: its arguments' slots
        std::vector<std::uint32_t> slots;
        for (const Expr a : arena.external_args(e)) slots.push_back(static_cast<std::uint32_t>(index.position(a)));
        ins.operand[1] = static_cast<std::uint32_t>(lists_.size());
        lists_.push_back(std::move(slots));
      }
    }
    instructions_.push_back(ins);
  }
  outputs_.reserve(outputs.size());
  for (const Expr out : outputs)
    outputs_.push_back(static_cast<std::uint32_t>(index.position(out)));
}

std::vector<double> Evaluator::evaluate(std::span<const double> leaf_values) const {
  std::vector<double> result(outputs_.size());
  std::vector<double> work;
  evaluate(leaf_values, result, work);
  return result;
}

void Evaluator::evaluate(std::span<const double> leaf_values, std::span<double> outputs,
                         std::vector<double>& work) const {
  if (leaf_values.size() != leaves_.size())
    throw std::invalid_argument("Evaluator: " + std::to_string(leaf_values.size()) +
                                " leaf values given, " + std::to_string(leaves_.size()) +
                                " expected");
  if (outputs.size() != outputs_.size())
    throw std::invalid_argument("Evaluator: output span has the wrong size");
  work.resize(instructions_.size());
  for (std::size_t i = 0; i < leaf_slots_.size(); ++i) work[leaf_slots_[i]] = leaf_values[i];
  for (std::size_t slot = 0; slot < instructions_.size(); ++slot) {
    const Instruction& ins = instructions_[slot];
    switch (ins.kind) {
    case ExprKind::Constant: work[slot] = constants_[ins.operand[0]]; break;
    case ExprKind::Symbol:
    case ExprKind::Der:
    case ExprKind::Pre:
    case ExprKind::Delay: break; // written from leaf_values above
    case ExprKind::ArgList: work[slot] = work[ins.operand[0]]; break;
    case ExprKind::External: {
      std::vector<double> args;
      for (const std::uint32_t s : lists_[ins.operand[1]]) args.push_back(work[s]);
      work[slot] = runtime::modelica_random::value(static_cast<int>(work[ins.operand[0]]), args);
      break;
    }
    case ExprKind::Add:
    case ExprKind::Sub:
    case ExprKind::Mul:
    case ExprKind::Div:
    case ExprKind::Neg:
    case ExprKind::Pow:
    case ExprKind::Sin:
    case ExprKind::Cos:
    case ExprKind::Tan:
    case ExprKind::Asin:
    case ExprKind::Acos:
    case ExprKind::Atan:
    case ExprKind::Atan2:
    case ExprKind::Sinh:
    case ExprKind::Cosh:
    case ExprKind::Tanh:
    case ExprKind::Exp:
    case ExprKind::Log:
    case ExprKind::Log10:
    case ExprKind::Sqrt:
    case ExprKind::Abs:
    case ExprKind::Sign:
    case ExprKind::Min:
    case ExprKind::Max:
    case ExprKind::Floor:
    case ExprKind::Ceil:
    case ExprKind::Select:
    case ExprKind::Lt:
    case ExprKind::Le:
    case ExprKind::Gt:
    case ExprKind::Ge:
    case ExprKind::Eq:
    case ExprKind::Ne:
    case ExprKind::And:
    case ExprKind::Or:
    case ExprKind::Not:
    case ExprKind::NoEvent:
    case ExprKind::Smooth: {
      const std::size_t n = arity(ins.kind);
      const double a = n > 0 ? work[ins.operand[0]] : 0.0;
      const double b = n > 1 ? work[ins.operand[1]] : 0.0;
      const double c = n > 2 ? work[ins.operand[2]] : 0.0;
      work[slot] = detail::apply_scalar(ins.kind, a, b, c);
      break;
    }
    }
  }
  for (std::size_t i = 0; i < outputs_.size(); ++i) outputs[i] = work[outputs_[i]];
}

std::vector<double> evaluate(const ExprArena& arena, std::span<const Expr> outputs,
                             const LeafValues& values) {
  const Evaluator evaluator(arena, outputs);
  std::vector<double> leaf_values;
  leaf_values.reserve(evaluator.leaves().size());
  for (const Expr leaf : evaluator.leaves()) {
    const auto found = values.find(leaf);
    if (found == values.end())
      throw std::invalid_argument("evaluate(): no value for " + to_modelica(arena, leaf));
    leaf_values.push_back(found->second);
  }
  return evaluator.evaluate(leaf_values);
}

} // namespace mo::symbolic
