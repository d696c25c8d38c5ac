// Tearing of nonlinear blocks; see tearing.hpp.
#include "tearing.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <unordered_map>

#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/substitute.hpp"
#include "mo/symbolic/traversal.hpp"
#include "solve.hpp"

namespace mo::symbolic::detail {

namespace {

constexpr int kMaxTries = 8;

/// The state of one try: which unknowns are known, which equations are done.
struct TryState {
  std::vector<char> known, done;
  std::vector<int> left;  ///< per equation: unknowns not yet known
  Tearing result;
};

class Tearer {
public:
  Tearer(ExprArena& a, const BlockEquations& b, const LeafValues& env) : a_(a), b_(b), env_(env) {
    std::unordered_map<Expr, std::size_t, ExprHash> local;
    for (std::size_t j = 0; j < b.unknowns.size(); ++j) local.emplace(b.unknowns[j], j);
    vars_of_.resize(b.residuals.size());
    eqs_of_.resize(b.unknowns.size());
    coefficient_.resize(b.residuals.size());
    for (std::size_t i = 0; i < b.residuals.size(); ++i) {
      for (Expr l : leaves(a, std::span(&b.residuals[i], 1)))
        if (const auto it = local.find(l); it != local.end()) {
          vars_of_[i].push_back(it->second);
          eqs_of_[it->second].push_back(i);
        }
      for (std::size_t v : vars_of_[i]) coefficient_[i].push_back(coefficient(b.residuals[i], b.unknowns[v]));
    }
  }

  Tearing choose() {
    std::vector<char> avoid(b_.unknowns.size(), 0);
    std::optional<Tearing> first;
    for (int attempt = 0; attempt < kMaxTries; ++attempt) {
      Tearing t = run(avoid);
      const std::optional<bool> ok = finite(t);
      if (!ok || *ok) return t;
      if (!first) first = t;
      bool added = false;
      for (std::size_t v : t.iteration) added = added || !avoid[v], avoid[v] = 1;
      if (!added) break;
    }
    return *first;
  }

  /// The explicit value of each causal unknown and the torn residuals, over
  /// the tearing variables.
  void build(const Tearing& t, ExprMap& values, std::vector<Expr>& torn) {
    for (const auto& [e, v] : t.causal) {
      Expr& value = values[b_.unknowns[v]];
      value = a_.constant(0.0);  // r at v = 0 is minus the coefficient times v
      value = a_.div(a_.neg(substitute(a_, b_.residuals[e], values)), *coefficient_of(e, v));
    }
    std::vector<Expr> res;
    for (std::size_t e : t.residual_eqs) res.push_back(b_.residuals[e]);
    torn = substitute(a_, res, values);
  }

private:
  /// ∂r/∂v when r is affine in v with a coefficient over parameters only,
  /// finite and nonzero at the parameters' values (so that solving for v
  /// divides by no quantity that may vanish during a simulation).
  std::optional<Expr> coefficient(Expr r, Expr v) {
    if (discontinuous_in(a_, r, std::span(&v, 1))) return std::nullopt;
    const Expr d = derivative(a_, r, v);
    if (a_.is_constant(d)) {
      const double c = a_.constant_value(d);
      return c != 0.0 && std::isfinite(c) ? std::optional<Expr>(d) : std::nullopt;
    }
    for (Expr l : leaves(a_, std::span(&d, 1)))
      if (a_.kind(l) != ExprKind::Symbol || a_.symbol_info(l).role != SymbolRole::Parameter)
        return std::nullopt;
    try {
      const double c = evaluate(a_, std::span(&d, 1), env_)[0];
      if (c == 0.0 || !std::isfinite(c)) return std::nullopt;
    } catch (const std::invalid_argument&) {
      return std::nullopt;
    }
    return d;
  }

  const std::optional<Expr>& coefficient_of(std::size_t e, std::size_t v) const {
    const auto& vs = vars_of_[e];
    const auto k = static_cast<std::size_t>(std::find(vs.begin(), vs.end(), v) - vs.begin());
    return coefficient_[e][k];
  }

  /// The one unknown of `e` not yet known (left[e] == 1).
  std::size_t last_unknown(const TryState& s, std::size_t e) const {
    for (std::size_t v : vars_of_[e])
      if (!s.known[v]) return v;
    throw std::logic_error("tearing: equation has no unknown left");
  }

  void mark_known(TryState& s, std::size_t v, std::vector<std::size_t>& work) const {
    s.known[v] = 1;
    for (std::size_t e : eqs_of_[v])
      if (!s.done[e] && --s.left[e] <= 1) work.push_back(e);
  }

  /// Solves every equation left with one unknown it is solvable for, and
  /// turns every equation left with none into a torn equation.
  void propagate(TryState& s, std::vector<std::size_t>& work) const {
    while (!work.empty()) {
      const std::size_t e = work.back();
      work.pop_back();
      if (s.done[e]) continue;
      if (s.left[e] == 0) {
        s.done[e] = 1;
        s.result.residual_eqs.push_back(e);
      } else if (s.left[e] == 1) {
        const std::size_t v = last_unknown(s, e);
        if (!coefficient_of(e, v)) continue;  // waits until v is known otherwise
        s.done[e] = 1;
        s.result.causal.emplace_back(e, v);
        mark_known(s, v, work);
      }
    }
  }

  /// Unknowns of the equation left solvable for its last unknown once `v` is known.
  int gain(const TryState& s, std::size_t v) const {
    int n = 0;
    for (std::size_t e : eqs_of_[v]) {
      if (s.done[e] || s.left[e] != 2) continue;
      for (std::size_t w : vars_of_[e])
        if (w != v && !s.known[w] && coefficient_of(e, w)) ++n;
    }
    return n;
  }

  bool given(std::size_t v) const { return v < b_.start_guess.size() && b_.start_guess[v]; }

  /// Cellier's choice among the unknowns not yet known (those not in `avoid`
  /// when there are any; of those, the ones whose start the author gave when
  /// there are any).
  std::size_t select(const TryState& s, const std::vector<char>& avoid) const {
    bool any_free = false;
    for (std::size_t v = 0; v < s.known.size(); ++v) any_free = any_free || (!s.known[v] && !avoid[v]);
    const auto open = [&](std::size_t v) { return !s.known[v] && (!any_free || !avoid[v]); };
    bool any_given = false;  // (0) an author's start value first
    for (std::size_t v = 0; v < s.known.size(); ++v) any_given = any_given || (open(v) && given(v));
    const auto candidate = [&](std::size_t v) { return open(v) && (!any_given || given(v)); };
    int most = -1;  // (1) equations with the most unknowns left that hold a candidate
    for (std::size_t e = 0; e < vars_of_.size(); ++e) {
      if (s.done[e] || s.left[e] <= most) continue;
      for (std::size_t v : vars_of_[e])
        if (candidate(v)) { most = s.left[e]; break; }
    }
    std::size_t best = s.known.size();
    int best_occ = -1, best_gain = -1;
    std::vector<char> seen(s.known.size(), 0);
    for (std::size_t e = 0; e < vars_of_.size(); ++e) {
      if (s.done[e] || s.left[e] != most) continue;
      for (std::size_t v : vars_of_[e]) {
        if (!candidate(v) || seen[v]) continue;
        seen[v] = 1;
        int occ = 0;  // (2) occurrences in the remaining equations
        for (std::size_t f : eqs_of_[v]) occ += s.done[f] ? 0 : 1;
        const int g = occ < best_occ ? -1 : gain(s, v);  // (3) equations made solvable
        if (occ > best_occ || (occ == best_occ && g > best_gain) ||
            (occ == best_occ && g == best_gain && v < best)) {
          best = v, best_occ = occ, best_gain = g;
        }
      }
    }
    if (best == s.known.size())  // unreachable for a matched block; keep the loop finite
      best = static_cast<std::size_t>(std::find(s.known.begin(), s.known.end(), 0) - s.known.begin());
    return best;
  }

  Tearing run(const std::vector<char>& avoid) const {
    TryState s = start_try();
    std::vector<std::size_t> work;
    for (;;) {
      const auto open = std::find(s.known.begin(), s.known.end(), 0);
      if (open == s.known.end()) break;
      const std::size_t v = select(s, avoid);
      s.result.iteration.push_back(v);
      mark_known(s, v, work);
      propagate(s, work);
    }
    return prune(std::move(s.result));
  }

  /// The try before any tearing: every equation with one unknown solved.
  TryState start_try() const {
    const std::size_t n = b_.unknowns.size();
    TryState s{std::vector<char>(n, 0), std::vector<char>(n, 0), std::vector<int>(n, 0), {}};
    std::vector<std::size_t> work;
    for (std::size_t e = 0; e < n; ++e) {
      s.left[e] = static_cast<int>(vars_of_[e].size());
      if (s.left[e] <= 1) work.push_back(e);
    }
    propagate(s, work);
    return s;
  }

  /// The causal order with `iteration` torn, in that order (one that an
  /// earlier one already makes explicit is left out); nullopt if some
  /// unknown is still open after them.
  std::optional<Tearing> with_iteration(const std::vector<std::size_t>& iteration) const {
    TryState s = start_try();
    std::vector<std::size_t> work;
    for (std::size_t v : iteration) {
      if (s.known[v]) continue;
      s.result.iteration.push_back(v);
      mark_known(s, v, work);
      propagate(s, work);
    }
    if (std::find(s.known.begin(), s.known.end(), 0) != s.known.end()) return std::nullopt;
    return std::move(s.result);
  }

  /// Drops the tearing variables that the others determine explicitly (the
  /// greedy choice takes a variable before the ones that later make it
  /// explicit: MultiBody's spring lengths before the joint position they
  /// follow from), the latest choice first; a variable with the author's
  /// start stays.
  Tearing prune(Tearing t) const {
    std::vector<std::size_t> kept = t.iteration;
    for (std::size_t k = kept.size(); k-- > 0;) {
      if (given(kept[k])) continue;
      std::vector<std::size_t> fewer = kept;
      fewer.erase(fewer.begin() + static_cast<std::ptrdiff_t>(k));
      if (with_iteration(fewer)) kept = std::move(fewer);
    }
    if (kept.size() == t.iteration.size()) return t;
    return *with_iteration(kept);
  }

  /// Whether the torn residuals and explicit values are finite with the
  /// tearing variables at their start values; nullopt if `env_` lacks a leaf.
  std::optional<bool> finite(const Tearing& t) {
    ExprMap values;
    std::vector<Expr> torn;
    build(t, values, torn);
    for (const auto& [e, v] : t.causal) torn.push_back(values.at(b_.unknowns[v]));
    LeafValues at = env_;
    for (std::size_t v : t.iteration) at[b_.unknowns[v]] = b_.start[v];
    try {
      const std::vector<double> r = evaluate(a_, torn, at);
      return std::all_of(r.begin(), r.end(), [](double x) { return std::isfinite(x); });
    } catch (const std::invalid_argument&) {
      return std::nullopt;
    }
  }

  ExprArena& a_;
  const BlockEquations& b_;
  const LeafValues& env_;
  std::vector<std::vector<std::size_t>> vars_of_;  ///< equation → its block unknowns
  std::vector<std::vector<std::size_t>> eqs_of_;   ///< unknown → equations using it
  std::vector<std::vector<std::optional<Expr>>> coefficient_;  ///< parallel to vars_of_
};

void set_origins(Step& step, const std::vector<std::string>& origins,
                 const std::vector<std::size_t>& rows) {
  const auto origin = [&](std::size_t i) { return rows[i] < origins.size() ? origins[rows[i]] : std::string(); };
  if (auto* as = std::get_if<Assignment>(&step)) {
    as->origin = origin(0);
    return;
  }
  auto& b = std::get<EquationBlock>(step);
  for (std::size_t i = 0; i < rows.size(); ++i) b.origins.push_back(origin(i));
}

}  // namespace

Tearing choose_tearing(ExprArena& arena, const BlockEquations& block, const LeafValues& at_start) {
  return Tearer(arena, block, at_start).choose();
}

std::vector<Step> solve_block_torn(ExprArena& a, const BlockEquations& block,
                                   const LeafValues& at_start, bool tear) {
  std::vector<std::size_t> all(block.residuals.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  std::vector<Step> out{solve_block(a, block.residuals, block.unknowns, block.start)};
  set_origins(out[0], block.origins, all);
  const auto* whole = std::get_if<EquationBlock>(&out[0]);
  if (!tear || !whole || whole->linear || block.unknowns.size() < 2) return out;
  try {
    Tearer tearer(a, block, at_start);
    const Tearing t = tearer.choose();
    if (t.causal.empty()) return out;
    ExprMap values;
    std::vector<Expr> torn, iteration;
    std::vector<double> start;
    tearer.build(t, values, torn);
    for (std::size_t v : t.iteration) {
      iteration.push_back(block.unknowns[v]);
      start.push_back(block.start[v]);
    }
    std::vector<Step> steps{solve_block(a, torn, iteration, start)};
    set_origins(steps[0], block.origins, t.residual_eqs);
    for (const auto& [e, v] : t.causal)
      steps.emplace_back(Assignment{block.unknowns[v], values.at(block.unknowns[v]),
                                    e < block.origins.size() ? block.origins[e] : std::string()});
    return steps;
  } catch (const std::invalid_argument&) {
    return out;  // an unknown under pre(): substitution by an expression is not defined
  }
}

}  // namespace mo::symbolic::detail
