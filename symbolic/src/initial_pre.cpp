// The pre() values of discrete variables before the event at initialisation;
// see dae_build.hpp (solve_initial_pre).
#include <algorithm>
#include <cmath>
#include <exception>
#include <unordered_map>

#include <fmt/format.h>

#include "dae_build.hpp"
#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic::detail {

namespace {

using frontend::DiagId;

class PreSolver {
public:
  PreSolver(Dae& dae, const std::vector<PreEquation>& eqs, const LeafValues& at_t0,
            const std::vector<bool>& boolean, frontend::DiagnosticEngine& diags)
      : dae_(dae), eqs_(eqs), known_(at_t0), boolean_(boolean), diags_(diags) {
    for (const PreEquation& eq : eqs_)
      for (const Expr side : {eq.lhs, eq.rhs})
        for (const Expr leaf : leaves(dae_.arena, std::span(&side, 1)))
          if (const int d = discrete_of(leaf); d >= 0) unknown_.emplace(leaf, d);
  }

  bool run() {
    std::vector<std::size_t> pending;
    for (std::size_t i = 0; i < eqs_.size(); ++i) pending.push_back(i);
    while (!pending.empty()) {
      if (propagate(pending)) continue;
      if (!start_values_for_one(pending)) return false;
    }
    for (const auto& [leaf, d] : unknown_)
      if (const auto it = known_.find(leaf); it != known_.end())
        dae_.discrete[static_cast<std::size_t>(d)].start = it->second;
    return ok_;
  }

private:
  /// The discrete variable whose pre() `leaf` is, or -1.
  int discrete_of(Expr leaf) const {
    const ExprArena& a = dae_.arena;
    if (a.kind(leaf) != ExprKind::Pre) return -1;
    const Expr w = a.operand(leaf, 0);
    if (a.kind(w) != ExprKind::Symbol || a.symbol_info(w).role != SymbolRole::Discrete) return -1;
    return a.symbol_info(w).index;
  }

  std::vector<Expr> open_leaves(const PreEquation& eq) const {
    std::vector<Expr> out;
    for (const Expr side : {eq.lhs, eq.rhs})
      for (const Expr leaf : leaves(dae_.arena, std::span(&side, 1)))
        if (unknown_.contains(leaf) && !known_.contains(leaf) &&
            std::find(out.begin(), out.end(), leaf) == out.end())
          out.push_back(leaf);
    return out;
  }

  double value(Expr e) const { return evaluate(dae_.arena, std::span(&e, 1), known_)[0]; }

  /// Solves every pending equation left with one open pre() value (a side
  /// that is that value, or a Boolean that one of false and true satisfies)
  /// and checks those with none; true if any was solved or checked.
  bool propagate(std::vector<std::size_t>& pending) {
    bool progress = false;
    for (std::size_t k = 0; k < pending.size();) {
      const PreEquation& eq = eqs_[pending[k]];
      const std::vector<Expr> open = open_leaves(eq);
      bool done = false;
      try {
        if (open.empty()) {
          check(eq);
          done = true;
        } else if (open.size() == 1) {
          done = solve_for(eq, open[0]);
        }
      } catch (const std::invalid_argument&) {
        fail(eq);
        done = true;
      }
      if (done) {
        pending.erase(pending.begin() + static_cast<std::ptrdiff_t>(k));
        progress = true;
      } else {
        ++k;
      }
    }
    return progress;
  }

  bool solve_for(const PreEquation& eq, Expr u) {
    if (eq.lhs == u || eq.rhs == u) {
      known_[u] = value(eq.lhs == u ? eq.rhs : eq.lhs);
      return true;
    }
    if (!boolean_[static_cast<std::size_t>(unknown_.at(u))]) return false;
    int fits = 0;
    double pick = 0.0;
    for (const double b : {0.0, 1.0}) {
      known_[u] = b;
      if (value(eq.lhs) == value(eq.rhs)) {
        ++fits;
        pick = b;
      }
    }
    known_.erase(u);
    if (fits != 1) return false;
    known_[u] = pick;
    return true;
  }

  void check(const PreEquation& eq) {
    const double l = value(eq.lhs), r = value(eq.rhs);
    if (std::fabs(l - r) <= 1e-10 * std::max({1.0, std::fabs(l), std::fabs(r)})) return;
    diags_.report(DiagId::UnsupportedInLowering, eq.range,
                  fmt::format("this initial equation contradicts the others on pre() values: its "
                              "sides evaluate to {:g} and {:g}", l, r));
    ok_ = false;
  }

  void fail(const PreEquation& eq) {
    std::string open;  // the values other than pre() ones it lacks, named as the flat model does
    for (const Expr side : {eq.lhs, eq.rhs})
      for (const Expr leaf : leaves(dae_.arena, std::span(&side, 1))) {
        const ExprKind k = dae_.arena.kind(leaf);
        if (known_.contains(leaf) || (k != ExprKind::Symbol && k != ExprKind::Der)) continue;
        const Expr sym = k == ExprKind::Symbol ? leaf : dae_.arena.operand(leaf, 0);
        const int var = dae_.var_of(sym);  // symbols of variables have internal names
        const std::string name = fmt::format(
            "{}{}{}", k == ExprKind::Der ? "der(" : "",
            var >= 0 ? dae_.vars[static_cast<std::size_t>(var)].info.name : dae_.arena.symbol_info(sym).name,
            k == ExprKind::Der ? ")" : "");
        if (open.find("'" + name + "'") == std::string::npos) open += (open.empty() ? "'" : ", '") + name + "'";
      }
    diags_.report(DiagId::UnsupportedInLowering, eq.range,
                  "pre() values in an initial equation must follow from parameters, time, "
                  "variables that equations give from those, and other pre() values" +
                      (open.empty() ? std::string() : " (no value for " + open + ")"));
    ok_ = false;
  }

  /// No equation has a single open value: the first one with a side that is
  /// a pre() value defines it, the other open values it reads keep their
  /// start values (as `fixed = true` would fix them).
  bool start_values_for_one(const std::vector<std::size_t>& pending) {
    for (const std::size_t i : pending) {
      const PreEquation& eq = eqs_[i];
      const std::vector<Expr> open = open_leaves(eq);
      for (const Expr target : {eq.lhs, eq.rhs}) {
        if (std::find(open.begin(), open.end(), target) == open.end()) continue;
        for (const Expr w : open)
          if (w != target)
            known_[w] = dae_.discrete[static_cast<std::size_t>(unknown_.at(w))].start;
        return true;
      }
    }
    fail(eqs_[pending.front()]);
    return false;
  }

  Dae& dae_;
  const std::vector<PreEquation>& eqs_;
  LeafValues known_;
  const std::vector<bool>& boolean_;
  frontend::DiagnosticEngine& diags_;
  std::unordered_map<Expr, int, ExprHash> unknown_;  ///< pre(d) → d's index in dae.discrete
  bool ok_ = true;
};

/// Adds to `known` (values at t0 of parameters and time) the continuous
/// variables that explicit equations `v = e` of dae.eqs give from known values
/// alone, to a fixed point: those values hold at t0 whatever the initial
/// system's other unknowns are (the MSL's AST_BatchPlant tank: a port height
/// given as `RealInput h2 = ...` from a parameter record through a connect()).
/// A non-finite value is not added.
void add_values_that_follow(const Dae& dae, LeafValues& known) {
  const ExprArena& a = dae.arena;
  // Per equation `v = e` (each side that is a continuous symbol): the symbols
  // of e still unknown; per symbol, the equations waiting for it.
  struct Explicit {
    Expr target, value;
    std::size_t open = 0;
  };
  std::vector<Explicit> eqs;
  std::unordered_map<Expr, std::vector<std::size_t>, ExprHash> waiting;
  auto continuous = [&](Expr e) {
    if (a.kind(e) != ExprKind::Symbol) return false;
    const SymbolRole r = a.symbol_info(e).role;
    return r == SymbolRole::Algebraic || r == SymbolRole::State;
  };
  for (const DaeEq& eq : dae.eqs) {
    if (eq.removed || a.kind(eq.residual) != ExprKind::Sub) continue;
    for (const std::size_t side : {0u, 1u}) {
      const Expr target = a.operand(eq.residual, side), value = a.operand(eq.residual, 1 - side);
      if (!continuous(target) || known.contains(target)) continue;
      std::vector<Expr> open;
      bool usable = true;
      for (const Expr leaf : leaves(a, std::span(&value, 1))) {
        if (known.contains(leaf)) continue;
        if (!continuous(leaf) || leaf == target) {  // der(), pre(), inputs, discrete values
          usable = false;
          break;
        }
        open.push_back(leaf);
      }
      if (!usable) continue;
      for (const Expr leaf : open) waiting[leaf].push_back(eqs.size());
      eqs.push_back({target, value, open.size()});  // `a = b` of two symbols: either way
    }
  }
  std::vector<std::size_t> ready;
  for (std::size_t i = 0; i < eqs.size(); ++i)
    if (eqs[i].open == 0) ready.push_back(i);
  while (!ready.empty()) {
    const Explicit& x = eqs[ready.back()];
    ready.pop_back();
    if (known.contains(x.target)) continue;
    double v = 0.0;
    try {
      v = evaluate(a, std::span(&x.value, 1), known)[0];
    } catch (const std::exception&) {  // a value the evaluator cannot compute stays unknown
      continue;
    }
    if (!std::isfinite(v)) continue;
    known[x.target] = v;
    if (const auto it = waiting.find(x.target); it != waiting.end())
      for (const std::size_t j : it->second)
        if (--eqs[j].open == 0) ready.push_back(j);
  }
}

}  // namespace

bool solve_initial_pre(Dae& dae, const std::vector<PreEquation>& eqs, const LeafValues& at_t0,
                       const std::vector<bool>& boolean, frontend::DiagnosticEngine& diags) {
  LeafValues known = at_t0;
  add_values_that_follow(dae, known);
  return PreSolver(dae, eqs, known, boolean, diags).run();
}

}  // namespace mo::symbolic::detail
