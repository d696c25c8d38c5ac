// One instruction as C++; see printer.hpp. The switch has no default: a new
// expression kind fails to compile here (-Werror=switch).
#include <fmt/format.h>

#include <stdexcept>

#include "mo/codegen/cpp_text.hpp"
#include "mo/symbolic/traversal.hpp"
#include "printer.hpp"

namespace mo::codegen::detail {

using symbolic::Expr;
using symbolic::ExprKind;

std::string operand_code(const symbolic::ExprArena& a, const Program& p, Expr e) {
  if (a.is_constant(e)) return cpp_double(a.constant_value(e));
  const Slot s = p.node_slots.at(e.id());
  if (s == no_slot) throw std::logic_error("internal error: code generation: operand without a slot");
  return fmt::format("w[{}]", s);
}

namespace {

std::string boolean(const std::string& condition) { return "(" + condition + ") ? 1.0 : 0.0"; }

std::string call(std::string_view f, const std::string& a) { return fmt::format("{}({})", f, a); }

/// True if `e` reads a discrete variable or a pre() value: only events change
/// those, so a change within an event iteration is the model's own, not
/// rounding.
bool reads_discrete(const symbolic::ExprArena& a, Expr e) {
  for (const Expr leaf : symbolic::leaves(a, std::span(&e, 1)))
    if (a.kind(leaf) == ExprKind::Pre ||
        (a.kind(leaf) == ExprKind::Symbol && a.symbol_info(leaf).role == symbolic::SymbolRole::Discrete))
      return true;
  return false;
}

}  // namespace

std::string node_code(const symbolic::ExprArena& ar, const Program& p, const Instruction& ins) {
  const Expr e = ins.node;
  const ExprKind k = ar.kind(e);
  const std::size_t n = symbolic::arity(k);
  std::string o[3];
  for (std::size_t i = 0; i < n; ++i) o[i] = operand_code(ar, p, ar.operand(e, i));
  std::string value;
  switch (k) {
  case ExprKind::Constant:
  case ExprKind::Symbol:
  case ExprKind::Der:
  case ExprKind::Pre:
  case ExprKind::Delay:  // loaded from the history (DelayCode)
    throw std::logic_error("internal error: code generation: a leaf as an instruction");
  case ExprKind::Add: value = o[0] + " + " + o[1]; break;
  case ExprKind::Sub: value = o[0] + " - " + o[1]; break;
  case ExprKind::Mul: value = o[0] + " * " + o[1]; break;
  case ExprKind::Div: value = o[0] + " / " + o[1]; break;
  case ExprKind::Neg: value = "-" + o[0]; break;
  case ExprKind::Pow:
    // x^2 as a product: exact, and cheaper than pow().
    if (ar.is_constant(ar.operand(e, 1), 2.0))
      value = o[0] + " * " + o[0];
    else
      value = fmt::format("std::pow({}, {})", o[0], o[1]);
    break;
  case ExprKind::Sin: value = call("std::sin", o[0]); break;
  case ExprKind::Cos: value = call("std::cos", o[0]); break;
  case ExprKind::Tan: value = call("std::tan", o[0]); break;
  case ExprKind::Asin: value = call("std::asin", o[0]); break;
  case ExprKind::Acos: value = call("std::acos", o[0]); break;
  case ExprKind::Atan: value = call("std::atan", o[0]); break;
  case ExprKind::Atan2: value = fmt::format("std::atan2({}, {})", o[0], o[1]); break;
  case ExprKind::Sinh: value = call("std::sinh", o[0]); break;
  case ExprKind::Cosh: value = call("std::cosh", o[0]); break;
  case ExprKind::Tanh: value = call("std::tanh", o[0]); break;
  case ExprKind::Exp: value = call("std::exp", o[0]); break;
  case ExprKind::Log: value = call("std::log", o[0]); break;
  case ExprKind::Log10: value = call("std::log10", o[0]); break;
  case ExprKind::Sqrt: value = call("std::sqrt", o[0]); break;
  case ExprKind::Abs: value = call("std::fabs", o[0]); break;
  case ExprKind::Sign: value = call("G::sign", o[0]); break;
  case ExprKind::Min: value = fmt::format("G::min({}, {})", o[0], o[1]); break;
  case ExprKind::Max: value = fmt::format("G::max({}, {})", o[0], o[1]); break;
  case ExprKind::Floor: value = call("std::floor", o[0]); break;
  case ExprKind::Ceil: value = call("std::ceil", o[0]); break;
  case ExprKind::Select: value = fmt::format("{} != 0 ? {} : {}", o[0], o[1], o[2]); break;
  case ExprKind::Lt: value = boolean(o[0] + " < " + o[1]); break;
  case ExprKind::Le: value = boolean(o[0] + " <= " + o[1]); break;
  case ExprKind::Gt: value = boolean(o[0] + " > " + o[1]); break;
  case ExprKind::Ge: value = boolean(o[0] + " >= " + o[1]); break;
  case ExprKind::Eq: value = boolean(o[0] + " == " + o[1]); break;
  case ExprKind::Ne: value = boolean(o[0] + " != " + o[1]); break;
  case ExprKind::And: value = boolean(o[0] + " != 0 && " + o[1] + " != 0"); break;
  case ExprKind::Or: value = boolean(o[0] + " != 0 || " + o[1] + " != 0"); break;
  case ExprKind::Not: value = boolean(o[0] + " == 0"); break;
  case ExprKind::NoEvent: value = o[0]; break;
  case ExprKind::Smooth: value = o[1]; break;
  case ExprKind::ArgList: value = o[0]; break;  // read through the External above it
  case ExprKind::External: {
    std::string args;
    for (const Expr a : ar.external_args(e)) args += (args.empty() ? "" : ", ") + operand_code(ar, p, a);
    value = fmt::format("G::modelica_random({}, {{{}}})", o[0], args);
    break;
  }
  }
  // A relation on an indicator a - b crossed at this instant: its value
  // follows the crossing. One that reads a discrete variable follows it only
  // while the indicator stays at zero (G::held_at_zero): a clause may move
  // it away in the event iteration (a timer restarted by its next step).
  if (ins.crossing >= 0) {
    const std::string held = reads_discrete(ar, e)
                                 ? fmt::format("cross[{}] != 0 && G::held_at_zero({}, {})", ins.crossing, o[0], o[1])
                                 : fmt::format("cross[{}] != 0", ins.crossing);
    value = fmt::format("{0} ? (cross[{1}] < 0 ? {2} : {3}) : ({4})", held, ins.crossing,
                        cpp_double(ins.value_if_down), cpp_double(1.0 - ins.value_if_down), value);
  }
  return value;
}

}  // namespace mo::codegen::detail
