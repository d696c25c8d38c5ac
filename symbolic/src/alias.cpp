// Alias elimination; see alias.hpp.
#include "alias.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_map>

#include "mo/symbolic/substitute.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic::detail {

namespace {

/// r = Σ coef·var + rest; coefficients and rest are time-invariant
/// (constants and parameters only).
struct LinearForm {
  std::vector<std::pair<int, Expr>> terms;
  Expr rest;
};

/// Whether an expression has a variable, time, input or discrete leaf (is not
/// a constant expression of parameters), memoised over the graph: the same
/// subexpressions are asked about at every product of every residual in every
/// pass (walking each one's leaves anew was quadratic in a large residual's
/// size: most of the MSL's EngineV6's lowering).
class TimeVarying {
public:
  explicit TimeVarying(const Dae& dae) : a_(dae.arena) {}

  bool operator()(Expr root) {
    if (const auto it = known_.find(root.id()); it != known_.end()) return it->second;
    std::vector<std::pair<Expr, bool>> stack{{root, false}};  // (node, operands pushed)
    while (!stack.empty()) {
      const auto [e, expanded] = stack.back();
      if (known_.contains(e.id())) {
        stack.pop_back();
        continue;
      }
      if (a_.is_leaf(e)) {  // Symbol, der(), pre(), delay(): only a parameter is not varying
        known_[e.id()] = a_.kind(e) != ExprKind::Symbol || a_.symbol_info(e).role != SymbolRole::Parameter;
        stack.pop_back();
        continue;
      }
      const std::size_t n = arity(a_.kind(e));
      if (!expanded) {
        stack.back().second = true;
        for (std::size_t i = 0; i < n; ++i) stack.emplace_back(a_.operand(e, i), false);
        continue;
      }
      bool varying = false;
      for (std::size_t i = 0; i < n; ++i) varying = varying || known_.at(a_.operand(e, i).id());
      known_[e.id()] = varying;
      stack.pop_back();
    }
    return known_.at(root.id());
  }

private:
  const ExprArena& a_;
  std::unordered_map<std::uint32_t, bool> known_;  ///< by node id
};

std::optional<LinearForm> linear_form(Dae& dae, Expr r, TimeVarying& time_varying) {
  ExprArena& a = dae.arena;
  LinearForm out;
  out.rest = a.constant(0.0);
  std::vector<std::pair<Expr, Expr>> stack{{r, a.constant(1.0)}};
  // The walk expands the residual as a tree: a subexpression shared by k
  // paths is walked k times. Composed aliases can share so deeply (the
  // MSL's EngineV6: one pass of the walks had not ended in 100 s) that a
  // residual past kMaxSteps is not taken for an alias equation; it stays an
  // equation, which is correct, only not simplified.
  constexpr std::size_t kMaxSteps = 100'000;
  for (std::size_t steps = 0; !stack.empty(); ++steps) {
    if (steps == kMaxSteps) return std::nullopt;
    auto [e, c] = stack.back();
    stack.pop_back();
    const ExprKind k = a.kind(e);
    if (k == ExprKind::Add || k == ExprKind::Sub) {
      stack.emplace_back(a.operand(e, 0), c);
      stack.emplace_back(a.operand(e, 1), k == ExprKind::Add ? c : a.neg(c));
    } else if (k == ExprKind::Neg) {
      stack.emplace_back(a.operand(e, 0), a.neg(c));
    } else if (k == ExprKind::Mul && !time_varying(a.operand(e, 0))) {
      stack.emplace_back(a.operand(e, 1), a.mul(c, a.operand(e, 0)));
    } else if (k == ExprKind::Mul && !time_varying(a.operand(e, 1))) {
      stack.emplace_back(a.operand(e, 0), a.mul(c, a.operand(e, 1)));
    } else if (const int v = k == ExprKind::Symbol ? dae.var_of(e) : none; v != none) {
      if (dae.vars[static_cast<std::size_t>(v)].eliminated) return std::nullopt;  // next pass
      auto it = std::find_if(out.terms.begin(), out.terms.end(),
                             [v](const auto& t) { return t.first == v; });
      if (it == out.terms.end()) {
        if (out.terms.size() == 2) return std::nullopt;
        out.terms.emplace_back(v, c);
      } else {
        it->second = a.add(it->second, c);
      }
    } else if (time_varying(e)) {
      return std::nullopt;
    } else {
      out.rest = a.add(out.rest, a.mul(c, e));
    }
  }
  std::erase_if(out.terms, [&](const auto& t) { return a.is_constant(t.second, 0.0); });
  return out;
}

class AliasEliminator {
public:
  explicit AliasEliminator(Dae& d) : dae_(d), a_(d.arena), time_varying_(d) {}

  AliasStats run() {
    AliasStats stats;
    for (bool changed = true; changed && stats.passes < 50;) {
      ++stats.passes;
      changed = false;
      std::vector<Expr*> residuals;
      for (DaeEq& eq : dae_.eqs)
        if (!eq.removed) residuals.push_back(&eq.residual);
      substitute_in_place(a_, residuals, all_);
      for (DaeEq& eq : dae_.eqs) {
        if (eq.removed) continue;
        if (try_eliminate(eq)) {
          eq.removed = true;
          changed = true;
        }
      }
      compose();
    }
    finish();
    stats.eliminated = eliminated_count_;
    return stats;
  }

private:
  DaeVar& var(int v) { return dae_.vars[static_cast<std::size_t>(v)]; }

  /// Higher is a better variable to keep.
  int score(int v) {
    const DaeVar& d = var(v);
    const auto dots = std::count(d.info.name.begin(), d.info.name.end(), '.');
    const int select = d.state_select == "always" ? 32 : d.state_select == "prefer" ? 16
                     : d.state_select == "avoid" ? -16 : d.state_select == "never" ? -32 : 0;
    return select + (d.derivative != none ? 8 : 0) + (d.fixed ? 4 : 0) + (d.start_given ? 2 : 0) -
           static_cast<int>(std::min<std::ptrdiff_t>(dots, 1));
  }

  /// A coefficient we may divide by: a nonzero number.
  bool divisible(Expr c) { return a_.is_constant(c) && a_.constant_value(c) != 0.0; }

  bool try_eliminate(const DaeEq& eq) {
    const auto form = linear_form(dae_, eq.residual, time_varying_);
    if (!form) return false;
    const auto& t = form->terms;
    if (t.size() == 1) {  // c·v + rest = 0
      if (var(t[0].first).integral != none || !divisible(t[0].second)) return false;
      Expr value = a_.div(a_.neg(form->rest), t[0].second);
      if (a_.is_constant(value)) value = a_.constant(a_.constant_value(value) + 0.0);  // no -0
      eliminate(t[0].first, value, Expr(), Expr());
      return true;
    }
    if (t.size() != 2) return false;
    if (a_.is_constant(form->rest, 0.0) && a_.is_constant(t[0].second) &&
        a_.is_constant(t[1].second) &&
        a_.constant_value(t[0].second) == -a_.constant_value(t[1].second) &&
        (derivative_link(t[0].first, t[1].first) || derivative_link(t[1].first, t[0].first)))
      return true;
    // Eliminate the lower-scored variable among those with a numeric
    // coefficient. A differentiated variable (a state candidate) is never
    // replaced through a scaled alias (k·keep + c with |k| ≠ 1): der(keep)
    // would become the state and its start value (0 by default) would put
    // the differentiated variable elsewhere than the model's start.
    const bool plain = a_.is_constant(t[0].second) && a_.is_constant(t[1].second) &&
                       std::abs(a_.constant_value(t[0].second)) == std::abs(a_.constant_value(t[1].second));
    int drop = -1, keep = -1;
    for (int i : {0, 1}) {
      const int j = 1 - i;
      if (!divisible(t[i].second) || var(t[i].first).integral != none ||
          var(t[j].first).integral != none || (!plain && var(t[i].first).derivative != none))
        continue;
      if (drop == -1 || score(t[i].first) < score(drop)) {
        drop = t[i].first;
        keep = t[j].first;
      }
    }
    if (drop == -1) return false;
    const std::size_t di = t[0].first == drop ? 0 : 1;
    // drop = k·keep + c with k = -c_keep/c_drop and c = -rest/c_drop.
    const Expr k = a_.neg(a_.div(t[1 - di].second, t[di].second));
    const Expr c = a_.neg(a_.div(form->rest, t[di].second));
    const Expr ks = var(keep).symbol;
    eliminate(drop, a_.add(a_.mul(k, ks), c), ks, k);
    inherit_start(keep, drop, k, c);
    inherit_state_select(keep, drop);
    return true;
  }

  /// An explicit stateSelect of `drop` that `keep` lacks becomes keep's: the
  /// author's word on the quantity outlives the name that carried it. The
  /// MSL's Body declares `r_0(stateSelect = StateSelect.avoid)` and is
  /// connected to a frame whose `r_0` says nothing; keeping the frame's name
  /// must not turn the body's position from avoided into a plain candidate
  /// (a root body's orientation would then be solved from positions, which
  /// cannot see the spin about the body's axis).
  void inherit_state_select(int keep, int drop) {
    if (var(keep).state_select.empty()) var(keep).state_select = var(drop).state_select;
  }

  /// v = der(x) with v not a derivative: v becomes der(x)'s replacement.
  bool derivative_link(int v, int dx) {
    if (var(dx).integral == none || var(v).integral != none) return false;
    const int x = var(dx).integral;
    if (x == v) return false;
    if (var(dx).derivative != none) return false;  // der(der(x)) exists: keep it simple
    var(x).derivative = v;
    var(v).integral = x;
    var(dx).integral = none;
    record(dx, var(v).symbol);
    inherit_start(v, dx, a_.constant(1.0), a_.constant(0.0));
    return true;
  }

  /// drop = factor·keep + offset (both time-invariant): a start value of
  /// `drop` that `keep` lacks becomes keep's, (start - offset)/factor. Without
  /// this, eliminating a differentiated variable (e.g. a capacitor voltage
  /// tied to a resistor current through R) would lose its initial value.
  void inherit_start(int keep, int drop, Expr factor, Expr offset) {
    DaeVar& k = var(keep);
    const DaeVar& d = var(drop);
    // An author's guess also replaces a start the class declared (not a fixed one).
    if (!((d.fixed && !k.fixed) || (d.start_given && !k.start_given) || (d.start_guess && !k.start_guess && !k.fixed)))
      return;
    if (a_.is_constant(offset, 0.0) && a_.is_constant(factor) && std::abs(a_.constant_value(factor)) == 1.0)
      k.start = a_.constant_value(factor) == 1.0 ? d.start : a_.neg(d.start);  // plain alias: no arithmetic
    else if (d.start.valid())
      k.start = a_.div(a_.sub(d.start, offset), factor);
    else
      return;
    k.fixed = k.fixed || d.fixed;
    k.start_given = true;
    k.start_guess = k.start_guess || d.start_guess;
  }

  /// drop := value; if drop has a derivative, it follows: k·der(keep), or 0
  /// when `keep` is invalid (value is constant in time). k is time-invariant.
  void eliminate(int drop, Expr value, Expr keep, Expr k) {
    record(drop, value);
    const int dd = var(drop).derivative;
    if (dd == none) return;
    var(drop).derivative = none;
    var(dd).integral = none;
    if (!keep.valid()) {
      eliminate(dd, a_.constant(0.0), Expr(), Expr());
      return;
    }
    const int kd = dae_.derivative_of(dae_.var_of(keep));
    const Expr ks = var(kd).symbol;
    eliminate(dd, a_.mul(k, ks), ks, k);
    // The derivative's start follows too: a mass's v(fixed = true) is the
    // initial velocity of the relative position that replaced its position.
    inherit_start(kd, dd, k, a_.constant(0.0));
  }

  void record(int v, Expr value) {
    var(v).eliminated = true;
    all_[var(v).symbol] = value;
    order_.push_back(v);
    ++eliminated_count_;
  }

  /// Values in `all_` may refer to variables eliminated after them: resolve
  /// until every value is over remaining variables; the next pass substitutes
  /// the resolved map into the residuals.
  void compose() {
    for (int round = 0; round < 64; ++round) {
      std::vector<Expr*> values;
      for (auto& [k, v] : all_)
        if (mentions_eliminated(v)) values.push_back(&v);
      if (values.empty()) return;
      // Jacobi-style: each round at least halves the longest alias chain.
      const ExprMap snapshot = all_;
      substitute_in_place(a_, values, snapshot);
    }
  }

  void finish() {
    for (int v : order_)
      if (!var(v).info.name.starts_with("der("))
        dae_.eliminated.push_back({var(v).info, all_.at(var(v).symbol)});
    std::vector<Expr*> targets;
    for (auto& y : dae_.outputs) targets.push_back(&y.value);
    for (auto& w : dae_.whens) {
      targets.push_back(&w.condition);
      for (auto& s : w.assignments) targets.push_back(&s.value);
      for (auto& [x, e] : w.reinits) targets.push_back(&e);
    }
    for (auto& d : dae_.vars)
      if (!d.eliminated && d.start.valid()) targets.push_back(&d.start);
    for (auto& eq : dae_.initial_eqs) targets.push_back(&eq.residual);
    substitute_in_place(a_, targets, all_);
  }

  /// True if `e` still mentions an eliminated variable.
  bool mentions_eliminated(Expr e) {
    for (Expr l : leaves(a_, std::span(&e, 1)))
      if (a_.kind(l) == ExprKind::Symbol && all_.contains(l)) return true;
    return false;
  }

  Dae& dae_;
  ExprArena& a_;
  TimeVarying time_varying_;
  ExprMap all_;      ///< every eliminated variable → its value
  std::vector<int> order_;
  std::size_t eliminated_count_ = 0;
};

}  // namespace

AliasStats eliminate_aliases(Dae& dae) { return AliasEliminator(dae).run(); }

}  // namespace mo::symbolic::detail
