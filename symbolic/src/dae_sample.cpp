// sample(start, interval) → the discrete flag its time events raise; see
// dae_build.hpp (sample_flag) and OdeSample.
#include <string>

#include "dae_build.hpp"
#include "dae_expr.hpp"
#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic::detail {

namespace ast = frontend::ast;
using frontend::DiagId;

namespace {

/// True if `e` reads only parameters, constants and the symbols of `also`
/// (no time, state, algebraic, input or discrete value).
bool over_parameters(const ExprArena& a, Expr e, const std::unordered_set<Expr, ExprHash>& also) {
  for (Expr leaf : leaves(a, std::span(&e, 1))) {
    if (also.contains(leaf)) continue;
    if (a.kind(leaf) != ExprKind::Symbol || a.symbol_info(leaf).role != SymbolRole::Parameter)
      return false;
  }
  return true;
}

}  // namespace

Expr sample_flag(Dae& dae, ExprConverter& conv, const ast::Expr& call, const LeafValues& parameters,
                 const std::unordered_set<Expr, ExprHash>& computed) {
  ExprArena& a = dae.arena;
  if (call.args.size() != 2 || !call.named.empty())
    return conv.fail(call, "sample() takes two arguments, sample(start, interval)");
  const Expr start = conv.convert(*call.args[0]), interval = conv.convert(*call.args[1]);
  if (!over_parameters(a, start, computed) || !over_parameters(a, interval, {}))
    return conv.fail(call, "sample(start, interval) needs an interval that is a parameter "
                           "expression and a start that is one, or reads parameters computed at "
                           "initialisation");
  double value = 0.0;
  try {
    value = evaluate(a, std::span(&interval, 1), parameters)[0];
  } catch (const std::invalid_argument&) {
    return conv.fail(call, "the interval of sample() cannot be evaluated at the parameters' values");
  }
  if (!(value > 0.0))
    return conv.fail(call, "the interval of sample() must be positive (it is " +
                               std::to_string(value) + ")");
  for (const OdeSample& s : dae.samples)
    if (s.start == start && s.interval == interval)
      return dae.discrete[static_cast<std::size_t>(s.flag)].symbol;
  const auto k = static_cast<std::int32_t>(dae.discrete.size());
  const std::string name = "sample(" + to_modelica(a, start) + ", " + to_modelica(a, interval) + ")";
  const Expr flag = a.symbol(name, SymbolRole::Discrete, k);
  dae.discrete.push_back({{name, "true at the time events of this sample()", ""}, flag, 0.0});
  dae.samples.push_back({k, start, interval});
  return flag;
}

}  // namespace mo::symbolic::detail
