// Time derivatives of the model's values for the initial system; see
// time_derivatives.hpp.
#include "time_derivatives.hpp"

#include <deque>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic::detail {

namespace {

class TimeDerivatives {
public:
  explicit TimeDerivatives(OdeModel& m) : m_(m), a_(m.arena) {
    for (std::size_t k = 0; k < m.steps.size(); ++k) {
      if (const auto* as = std::get_if<Assignment>(&m.steps[k])) {
        step_of_.emplace(as->target, k);
        continue;
      }
      for (Expr z : std::get<EquationBlock>(m.steps[k]).unknowns) step_of_.emplace(z, k);
    }
    for (const OdeState& x : m.states) derivative_.emplace(x.symbol, x.derivative);
  }

  /// d/dt of `e`, making the unknowns it needs.
  Expr of(Expr e) {
    ExprMap seeds;
    for (Expr l : leaves(a_, std::span(&e, 1)))
      if (const std::optional<Expr> d = of_leaf(l)) seeds[l] = *d;
    return forward_derivative(a_, e, seeds);
  }

  /// Differentiates the steps queued so far, and those they need.
  void finish() {
    while (!queue_.empty()) {
      const std::size_t k = queue_.front();
      queue_.pop_front();
      if (const auto* as = std::get_if<Assignment>(&m_.steps[k])) {
        out_.equations.emplace_back(a_.sub(derivative_.at(as->target), of(as->value)),
                                    "d/dt of " + as->origin);
        continue;
      }
      const auto& b = std::get<EquationBlock>(m_.steps[k]);
      for (Expr z : b.unknowns) of_leaf(z);
      for (std::size_t i = 0; i < b.residuals.size(); ++i)
        out_.equations.emplace_back(of(b.residuals[i]), "d/dt of " + (i < b.origins.size() ? b.origins[i] : ""));
    }
  }

  TimeDerivativeRows& result() { return out_; }

private:
  /// d/dt of a leaf; nullopt where it is 0 (parameters, discrete variables,
  /// pre(), inputs: those are flagged).
  std::optional<Expr> of_leaf(Expr l) {
    if (a_.kind(l) != ExprKind::Symbol) return std::nullopt;
    if (const auto it = derivative_.find(l); it != derivative_.end()) return it->second;
    const SymbolRole role = a_.symbol_info(l).role;
    if (role == SymbolRole::Time) return a_.constant(1.0);
    if (role == SymbolRole::Input) {
      out_.input_reached = true;
      return std::nullopt;
    }
    const auto step = step_of_.find(l);
    if (step == step_of_.end()) return std::nullopt;
    const Expr d = a_.symbol("$d/dt(" + a_.symbol_info(l).name + ")", SymbolRole::Algebraic, -1);
    derivative_.emplace(l, d);
    out_.unknowns.push_back(d);
    if (queued_.insert(step->second).second) queue_.push_back(step->second);
    return d;
  }

  OdeModel& m_;
  ExprArena& a_;
  std::unordered_map<Expr, std::size_t, ExprHash> step_of_;  ///< value → the step computing it
  ExprMap derivative_;  ///< state or computed value → its derivative symbol
  std::unordered_set<std::size_t> queued_;
  std::deque<std::size_t> queue_;
  TimeDerivativeRows out_;
};

}  // namespace

TimeDerivativeRows time_derivative_rows(OdeModel& model, const std::vector<std::pair<Expr, Expr>>& wanted) {
  TimeDerivatives t(model);
  std::vector<std::pair<Expr, std::string>> defined;
  for (const auto& [symbol, value] : wanted) {
    t.result().unknowns.push_back(symbol);
    defined.emplace_back(model.arena.sub(symbol, t.of(value)), "");
  }
  t.finish();
  TimeDerivativeRows out = std::move(t.result());
  out.equations.insert(out.equations.end(), defined.begin(), defined.end());
  return out;
}

}  // namespace mo::symbolic::detail
