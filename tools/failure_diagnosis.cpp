// Naming the equation behind a non-finite value; see failure_diagnosis.hpp.
#include "failure_diagnosis.hpp"

#include <fmt/format.h>

#include <cmath>

#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/ode_interpreter.hpp"
#include "mo/symbolic/printer.hpp"

namespace mo::tools {

namespace {

using symbolic::Expr;

/// "a = 1, b = 0" for the leaves of `e` (at most 12), values from the interpreter.
std::string leaf_values(const symbolic::OdeModel& ode, const symbolic::OdeInterpreter& in, Expr e,
                        bool& all_finite) {
  const symbolic::Evaluator ev(ode.arena, std::span(&e, 1));
  std::string out;
  std::size_t shown = 0;
  all_finite = true;
  for (Expr leaf : ev.leaves()) {
    const Expr key = ode.arena.kind(leaf) == symbolic::ExprKind::Pre ? ode.arena.operand(leaf, 0) : leaf;
    double v = std::nan("");
    try {
      v = in.value(key);
    } catch (const std::exception&) {
      continue;  // not computed (after a failed block)
    }
    all_finite = all_finite && std::isfinite(v);
    if (shown++ < 12) out += fmt::format("{}{} = {:g}", out.empty() ? "" : ", ", symbolic::to_modelica(ode.arena, leaf), v);
  }
  return out;
}

std::string where(const std::string& origin) { return origin.empty() ? "(no source location)" : origin; }

}  // namespace

std::string explain_non_finite(const symbolic::OdeModel& ode, double t, std::span<const double> x,
                               std::span<const double> u, std::span<const double> p,
                               std::span<const double> d) {
  symbolic::OdeInterpreter in(ode);
  std::string block_failure;
  try {
    (void)in.rhs(t, x, u, p, d);
  } catch (const std::exception& e) {
    block_failure = e.what();  // the steps after the failed block are not evaluated
  }
  for (const symbolic::Step& step : ode.steps) {
    if (const auto* a = std::get_if<symbolic::Assignment>(&step)) {
      double v = 0.0;
      try {
        v = in.value(a->target);
      } catch (const std::exception&) {
        break;  // not reached: a block before it failed
      }
      if (std::isfinite(v)) continue;
      bool operands_finite = true;
      const std::string values = leaf_values(ode, in, a->value, operands_finite);
      if (!operands_finite) continue;  // only passes on an earlier non-finite value
      return fmt::format("{}\n  {} = {} is {} at t = {}\n  with {}", where(a->origin),
                         symbolic::to_modelica(ode.arena, a->target), symbolic::to_modelica(ode.arena, a->value),
                         v, t, values);
    }
  }
  return block_failure;
}

}  // namespace mo::tools
