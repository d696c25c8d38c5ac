// Pantelides' algorithm and dummy-derivative state selection; see
// index_reduction.hpp.
#include "index_reduction.hpp"
#include "tiered_matching.hpp"
#include "dummy_pivots.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>
#include <fmt/format.h>

#include "dae_build.hpp"
#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/structure.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic::detail {

using frontend::DiagId;

namespace {

std::size_t at(int i) { return static_cast<std::size_t>(i); }

std::vector<int> unknowns_of(const Dae& dae, Expr residual) {
  std::vector<int> out;
  for (Expr l : leaves(dae.arena, std::span(&residual, 1))) {
    if (dae.arena.kind(l) != ExprKind::Symbol) continue;
    const int v = dae.var_of(l);
    if (v != none && !dae.vars[at(v)].eliminated) out.push_back(v);
  }
  return out;
}

/// Pantelides' algorithm with an iterative augmenting-path search.
class Pantelides {
public:
  Pantelides(Dae& d, frontend::DiagnosticEngine& diags)
      : dae_(d), diags_(diags), inc_(incidence(d)) {}

  bool run() {
    assign_.assign(dae_.vars.size(), none);
    const std::size_t original = dae_.eqs.size();
    for (std::size_t k = 0; k < original; ++k) {
      if (dae_.eqs[k].removed) continue;
      int i = static_cast<int>(k);
      for (int depth = 0;; ++depth) {
        if (augment(i)) break;
        if (depth == kMaxDepth || inc_[at(i)].empty()) return singular(i);
        if (!differentiate(i)) return false;
        i = dae_.eqs[at(i)].derivative;
      }
    }
    return true;
  }

private:
  static constexpr int kMaxDepth = 6;

  /// A DFS frame: equation, next incidence position, the variable that led here.
  struct Frame {
    int eq;
    std::size_t next;
    int via;
  };

  bool active(int v) const { return dae_.vars[at(v)].derivative == none; }

  /// Augmenting path from equation `root` over active variables; colours what it visits.
  bool augment(int root) {
    colored_eqs_.clear();
    colored_vars_.clear();
    ++stamp_;
    var_mark_.resize(dae_.vars.size(), 0);
    eq_mark_.resize(dae_.eqs.size(), 0);
    auto var_seen = [&](int v) { return var_mark_[at(v)] == stamp_; };
    auto eq_seen = [&](int e) { return eq_mark_[at(e)] == stamp_; };
    std::vector<Frame> stack{{root, 0, none}};
    eq_mark_[at(root)] = stamp_;
    colored_eqs_.push_back(root);
    // Cheap pass: a free active variable in the root equation.
    for (int v : inc_[at(root)])
      if (active(v) && assign_[at(v)] == none) {
        assign_[at(v)] = root;
        return true;
      }
    while (!stack.empty()) {
      Frame& f = stack.back();
      const auto& vars = inc_[at(f.eq)];
      if (f.next == vars.size()) {
        stack.pop_back();
        continue;
      }
      const int v = vars[f.next++];
      if (!active(v) || var_seen(v)) continue;
      var_mark_[at(v)] = stamp_;
      colored_vars_.push_back(v);
      const int owner = assign_[at(v)];
      if (owner == none) return flip(stack, v);
      if (eq_seen(owner)) continue;
      eq_mark_[at(owner)] = stamp_;
      colored_eqs_.push_back(owner);
      for (int w : inc_[at(owner)])
        if (active(w) && assign_[at(w)] == none) {
          stack.push_back({owner, 0, v});
          return flip(stack, w);
        }
      stack.push_back({owner, 0, v});
    }
    return false;
  }

  /// Reassigns along the DFS stack ending in free variable `v`.
  bool flip(const std::vector<Frame>& stack, int v) {
    for (std::size_t i = stack.size(); i-- > 0;) {
      assign_[at(v)] = stack[i].eq;
      v = stack[i].via;
    }
    return true;
  }

  bool differentiate(int root) {
    for (int v : colored_vars_) {
      const int d = dae_.derivative_of(v);
      if (assign_.size() < dae_.vars.size()) assign_.resize(dae_.vars.size(), none);
      (void)d;
    }
    for (int e : colored_eqs_) {
      bool input_hit = false;
      DaeEq de;
      de.residual = time_derivative(dae_, dae_.eqs[at(e)].residual, input_hit);
      if (assign_.size() < dae_.vars.size()) assign_.resize(dae_.vars.size(), none);
      if (input_hit) {
        diags_.report(DiagId::DifferentiatedInput, dae_.eqs[at(e)].range,
                      "index reduction must differentiate this equation, which involves a "
                      "top-level input; inputs cannot be differentiated");
        return false;
      }
      de.range = dae_.eqs[at(e)].range;
      de.integral = e;
      de.lhs_var = dae_.eqs[at(e)].lhs_var;
      const int index = static_cast<int>(dae_.eqs.size());
      dae_.eqs[at(e)].derivative = index;
      dae_.eqs.push_back(de);
      inc_.push_back(unknowns_of(dae_, de.residual));
    }
    for (int v : colored_vars_)
      assign_[at(dae_.vars[at(v)].derivative)] = dae_.eqs[at(assign_[at(v)])].derivative;
    (void)root;
    return true;
  }

  bool singular(int eq) {
    auto& d = diags_.report(DiagId::StructurallySingular, dae_.eqs[at(eq)].range,
                            "the system is structurally singular: this equation cannot be "
                            "solved for any unknown, even after differentiation");
    (void)d;
    int shown = 0;
    for (int v : colored_vars_) {
      if (++shown > 8) break;
      diags_.note(dae_.vars[at(v)].range,
                  "competing for '" + dae_.vars[at(v)].info.name + "'");
    }
    return false;
  }

  Dae& dae_;
  frontend::DiagnosticEngine& diags_;
  std::vector<std::vector<int>> inc_;
  std::vector<int> assign_;
  std::vector<int> colored_eqs_, colored_vars_;
  std::vector<int> var_mark_, eq_mark_;  ///< == stamp_: visited by this search
  int stamp_ = 0;
};

/// Root equation of `e`'s differentiation chain.
int chain_root(const Dae& dae, int e) {
  while (dae.eqs[at(e)].integral != none) e = dae.eqs[at(e)].integral;
  return e;
}

int chain_base(const Dae& dae, int v) {
  while (dae.vars[at(v)].integral != none) v = dae.vars[at(v)].integral;
  return v;
}

/// Lower is a better dummy for equation `e`.
int dummy_rank(const Dae& dae, int e, int v) {
  const std::string& ss = dae.vars[at(chain_base(dae, v))].state_select;
  if (ss == "always") return 100;
  int rank = 10;
  if (ss == "prefer") rank += 20;
  if (ss == "never") rank -= 8;
  if (ss == "avoid") rank -= 4;
  // Then a variable with a `fixed = true` start, the author's initial
  // condition (+9 +2, above any derivative with a start value): a better
  // state than one the model only differentiates (a medium's smoothed state,
  // `der_T = der(state.T)`, whose weight on the volume's temperature is 0 at
  // the start, would leave that temperature undefined). Then the variables
  // the model differentiates (with a constant coefficient first, as a
  // capacitor's C·der(v)), then those with a start value.
  const DaeVar& base = dae.vars[at(chain_base(dae, v))];
  if (base.source_derivative) rank += base.linear_derivative ? 8 : 6;
  if (base.start_given) rank += 2;
  if (base.fixed) rank += 9;
  if (chain_base(dae, v) == dae.eqs[at(chain_root(dae, e))].lhs_var) rank -= 2;
  return rank;
}

/// Values of every variable at its start (derivatives 0), parameters at
/// their defaults, time 0: the point where dummy pivots are compared.
LeafValues start_point(const Dae& dae) {
  LeafValues values;
  for (const auto& p : dae.parameters) values[p.symbol] = p.value;
  values[dae.time] = 0.0;
  for (const auto& u : dae.inputs) values[u.symbol] = 0.0;
  for (const auto& d : dae.discrete) values[d.symbol] = d.start;
  LeafValues out = values;
  for (const DaeVar& v : dae.vars) {
    double x = 0.0;
    if (v.start.valid()) {
      try {
        x = evaluate(dae.arena, std::span(&v.start, 1), values)[0];
      } catch (const std::invalid_argument&) {
      }
    }
    out[v.symbol] = x;
  }
  return out;
}

/// Every variable and derivative, time and the inputs at values drawn from
/// [0.5, 2] (fixed seed), parameters at their defaults: a point in general
/// position, where a Jacobian that is singular at every point shows it.
LeafValues general_point(const Dae& dae) {
  std::mt19937_64 g(20261127);
  std::uniform_real_distribution<double> draw(0.5, 2.0);
  LeafValues values;
  for (const auto& p : dae.parameters) values[p.symbol] = p.value;
  values[dae.time] = draw(g);
  for (const auto& u : dae.inputs) values[u.symbol] = draw(g);
  for (const auto& d : dae.discrete) values[d.symbol] = d.start;
  for (const DaeVar& v : dae.vars) values[v.symbol] = draw(g);
  return values;
}

/// ∂residual/∂v at each of `points` (0 where it cannot be evaluated or is
/// not finite).
std::vector<double> jacobian_entry(Dae& dae, const std::vector<const LeafValues*>& points, int e,
                                   int v) {
  const Expr d = derivative(dae.arena, dae.eqs[at(e)].residual, dae.vars[at(v)].symbol);
  std::vector<double> out;
  for (const LeafValues* point : points) {
    try {
      const double x = evaluate(dae.arena, std::span(&d, 1), *point)[0];
      out.push_back(std::isfinite(x) ? x : 0.0);
    } catch (const std::invalid_argument&) {
      out.push_back(0.0);
    }
  }
  return out;
}

/// ∂g/∂v of one equation of a level at the start point and at a general point.
struct LevelEntry {
  std::size_t row, col;
  double at_start, at_general;
};

/// Replaces a choice of dummies that is singular on the level's Jacobian at
/// the start point and at a general point (so the singularity is not the start
/// values' accident) by one that is regular at the general point
/// (dummy_pivots.hpp), where there is one. A choice regular at the start
/// point is kept.
void make_regular(std::size_t rows, const std::vector<int>& columns, const std::vector<LevelEntry>& entries,
                  const std::vector<int>& cost, std::vector<int>& dummy_of) {
  if (rows * columns.size() > 1'000'000) return;
  DenseJacobian at_start(rows, std::vector<double>(columns.size(), 0.0));
  DenseJacobian at_general = at_start;
  for (const LevelEntry& e : entries) {
    at_start[e.row][e.col] = e.at_start;
    at_general[e.row][e.col] = e.at_general;
  }
  if (regular_choice(at_start, dummy_of) || regular_choice(at_general, dummy_of)) return;
  if (auto regular = regular_columns(at_general, cost)) dummy_of = std::move(*regular);
}

}  // namespace

std::vector<std::vector<int>> incidence(const Dae& dae) {
  std::vector<std::vector<int>> out(dae.eqs.size());
  for (std::size_t e = 0; e < dae.eqs.size(); ++e)
    if (!dae.eqs[e].removed) out[e] = unknowns_of(dae, dae.eqs[e].residual);
  return out;
}

bool pantelides(Dae& dae, frontend::DiagnosticEngine& diags) {
  return structurally_regular(dae, diags) && Pantelides(dae, diags).run();
}

void report_singular(const Dae& dae, const std::vector<int>& eqs, const std::vector<int>& vars,
                     frontend::DiagnosticEngine& diags) {
  for (std::size_t i = 0; i < eqs.size() && i < 10; ++i)
    diags.report(DiagId::StructurallySingular, dae.eqs[at(eqs[i])].range,
                 "structurally singular: this equation has no unknown left to solve for "
                 "(the system is over-determined here)");
  for (std::size_t j = 0; j < vars.size() && j < 10; ++j) {
    const DaeVar& v = dae.vars[at(vars[j])];
    diags.report(DiagId::StructurallySingular, v.range,
                 "structurally singular: no equation is left to determine '" + v.info.name +
                     "' (the system is under-determined here)");
  }
}

bool structurally_regular(const Dae& dae, frontend::DiagnosticEngine& diags) {
  // Each variable counts together with its derivatives: Pantelides terminates
  // exactly when this matching is perfect (else no differentiation helps).
  std::vector<int> column(dae.vars.size(), none), base_of;
  std::vector<std::vector<int>> rows;
  std::vector<int> eqs;
  const auto inc = incidence(dae);
  for (std::size_t e = 0; e < dae.eqs.size(); ++e) {
    if (dae.eqs[e].removed) continue;
    std::vector<int> row;
    for (int v : inc[e]) {
      const int b = chain_base(dae, v);
      if (column[at(b)] == none) {
        column[at(b)] = static_cast<int>(base_of.size());
        base_of.push_back(b);
      }
      row.push_back(column[at(b)]);
    }
    rows.push_back(std::move(row));
    eqs.push_back(static_cast<int>(e));
  }
  for (std::size_t v = 0; v < dae.vars.size(); ++v)  // variables in no equation
    if (!dae.vars[v].eliminated && dae.vars[v].integral == none && column[v] == none) {
      column[v] = static_cast<int>(base_of.size());
      base_of.push_back(static_cast<int>(v));
    }
  const Matching m =
      maximum_matching(Incidence::from_lists(static_cast<int>(base_of.size()), rows));
  if (m.size == static_cast<int>(rows.size()) && m.size == static_cast<int>(base_of.size()))
    return true;
  std::vector<int> bad_eqs, bad_vars;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (m.unknown_of[i] == none) bad_eqs.push_back(eqs[i]);
  for (std::size_t j = 0; j < base_of.size(); ++j)
    if (m.equation_of[j] == none) bad_vars.push_back(base_of[j]);
  report_singular(dae, bad_eqs, bad_vars, diags);
  return false;
}

std::vector<bool> select_states(Dae& dae) {
  const LeafValues point = start_point(dae);
  const LeafValues general = general_point(dae);
  std::vector<bool> state(dae.vars.size(), false);
  for (std::size_t v = 0; v < dae.vars.size(); ++v)
    state[v] = !dae.vars[v].eliminated && dae.vars[v].derivative != none;
  const auto inc = incidence(dae);
  std::vector<int> level;  // G_j: differentiated equations at the top of their chains
  for (std::size_t e = 0; e < dae.eqs.size(); ++e)
    if (!dae.eqs[e].removed && dae.eqs[e].integral != none && dae.eqs[e].derivative == none)
      level.push_back(static_cast<int>(e));
  std::vector<char> candidate(dae.vars.size(), 0);
  for (std::size_t v = 0; v < dae.vars.size(); ++v)
    candidate[v] = dae.vars[v].derivative == none && dae.vars[v].integral != none;
  while (!level.empty()) {
    std::vector<int> columns;  // candidate variables of this level, by local index
    std::vector<int> local(dae.vars.size(), none);
    std::vector<std::vector<CostEdge>> rows;
    std::vector<LevelEntry> entries;  // the level's Jacobian, at both points
    std::vector<int> cost;            // per column: its cheapest edge
    for (int e : level) {
      // (rank, -|pivot at start|), v, ∂g/∂v at start and at the general point
      std::vector<std::tuple<std::pair<int, double>, int, std::vector<double>>> keyed;
      for (int v : inc[at(e)]) {
        if (!candidate[at(v)]) continue;
        std::vector<double> values = jacobian_entry(dae, {&point, &general}, e, v);
        keyed.emplace_back(std::pair{dummy_rank(dae, e, v), -std::abs(values[0])}, v, std::move(values));
      }
      std::stable_sort(keyed.begin(), keyed.end(),
                       [](const auto& a, const auto& b) { return std::get<0>(a) < std::get<0>(b); });
      std::vector<CostEdge> row;
      for (const auto& [key, v, values] : keyed) {
        if (local[at(v)] == none) {
          local[at(v)] = static_cast<int>(columns.size());
          columns.push_back(v);
          cost.push_back(key.first);
        }
        cost[at(local[at(v)])] = std::min(cost[at(local[at(v)])], key.first);
        row.push_back({local[at(v)], key.first});
        entries.push_back({rows.size(), at(local[at(v)]), values[0], values[1]});
      }
      rows.push_back(std::move(row));
    }
    // Dummies by rank: the best-ranked dummies of all equations of the level
    // together, not equation by equation.
    std::vector<int> dummy_of = tiered_matching(rows, static_cast<int>(columns.size()));
    make_regular(level.size(), columns, entries, cost, dummy_of);
    std::fill(candidate.begin(), candidate.end(), 0);
    std::vector<int> next;
    for (std::size_t r = 0; r < level.size(); ++r) {
      const int col = dummy_of[r];
      if (col == none) continue;
      const int dummy = columns[at(col)];
      const int integral = dae.vars[at(dummy)].integral;
      state[at(integral)] = false;  // its derivative is a dummy: not a state
      if (dae.vars[at(integral)].integral != none) candidate[at(integral)] = 1;
      const int lower = dae.eqs[at(level[r])].integral;
      if (dae.eqs[at(lower)].integral != none) next.push_back(lower);
    }
    level = std::move(next);
  }
  return state;
}

}  // namespace mo::symbolic::detail
