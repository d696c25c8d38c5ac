// The initial system at t0; see initial_system.hpp.
#include "initial_system.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "mo/symbolic/structure.hpp"
#include "mo/symbolic/substitute.hpp"
#include "mo/symbolic/traversal.hpp"
#include "solve.hpp"
#include "tearing.hpp"
#include "tiered_matching.hpp"
#include "time_derivatives.hpp"

namespace mo::symbolic::detail {

using frontend::DiagId;

namespace {

/// Where a row of the initial system comes from.
enum class RowKind {
  Model,     ///< a residual of the model's steps
  Initial,   ///< an initial equation
  Fixed,     ///< x = start of a state declared fixed = true
  FixedAlgebraic, ///< v = start of another variable declared fixed = true: used
                  ///< when the system admits it (before any StartGuess), else
                  ///< dropped with a warning
  StartGuess ///< x = start of a state, used only if the system needs it
};

struct Row {
  Expr residual;
  RowKind kind;
  std::string origin;           ///< for messages
  frontend::SourceRange range;  ///< initial equations only
  std::size_t state = 0;        ///< StartGuess and fixed states: the state's index
};

class InitialSystem {
public:
  InitialSystem(OdeModel& m, const InitialInput& in, frontend::DiagnosticEngine& diags)
      : m_(m), a_(m.arena), in_(in), diags_(diags) {}

  bool run() {
    unknowns();
    rows();
    if (!time_derivatives()) return false;
    const std::vector<int> col_of = match();
    if (!check(col_of)) return false;
    warn_free_states(col_of);
    solve(col_of);
    return true;
  }

private:
  void add_unknown(Expr s, double guess) {
    local_.emplace(s, static_cast<int>(unknowns_.size()));
    unknowns_.push_back(s);
    guess_.push_back(guess);
  }

  double guess_of(Expr s) const {
    const auto it = in_.guess.find(s);
    return it == in_.guess.end() ? 0.0 : it->second;
  }

  void unknowns() {
    for (const OdeState& x : m_.states) add_unknown(x.symbol, guess_of(x.symbol));
    for (const OdeState& x : m_.states) add_unknown(x.derivative, 0.0);
    for (const OdeAlgebraic& y : m_.algebraics) add_unknown(y.symbol, guess_of(y.symbol));
  }

  /// The model's equations at t0, where delay(e) is e (undelayed()).
  void rows() {
    for (const Step& s : m_.steps) {
      if (const auto* as = std::get_if<Assignment>(&s)) {
        rows_.push_back({undelayed(a_, a_.sub(as->target, as->value)), RowKind::Model, as->origin, {}, 0});
        continue;
      }
      const auto& b = std::get<EquationBlock>(s);
      for (std::size_t i = 0; i < b.residuals.size(); ++i)
        rows_.push_back({undelayed(a_, b.residuals[i]), RowKind::Model, i < b.origins.size() ? b.origins[i] : "", {}, 0});
    }
    for (const InitialEquation& e : in_.equations)
      rows_.push_back({undelayed(a_, e.residual), RowKind::Initial, e.origin, e.range, 0});
    for (std::size_t i = 0; i < m_.states.size(); ++i) {
      const OdeState& x = m_.states[i];
      const RowKind k = x.fixed ? RowKind::Fixed : RowKind::StartGuess;
      rows_.push_back({a_.sub(x.symbol, x.start), k, x.info.name + " = its start value", {}, i});
    }
    for (const auto& [v, start] : in_.fixed_algebraics)
      rows_.push_back({a_.sub(v, start), RowKind::FixedAlgebraic,
                       a_.symbol_info(v).name + " = its start value (fixed = true)", {}, 0});
  }

  /// The unknowns and rows of der(y) in the initial equations
  /// (InitialInput::time_derivatives); false after reporting an input.
  bool time_derivatives() {
    if (in_.time_derivatives.empty()) return true;
    const TimeDerivativeRows t = time_derivative_rows(m_, in_.time_derivatives);
    if (t.input_reached) {
      diags_.report(DiagId::DifferentiatedInput, first_initial_range(),
                    "der() in an initial equation of a variable that depends on an input: "
                    "inputs cannot be differentiated");
      return false;
    }
    for (Expr u : t.unknowns) add_unknown(u, 0.0);
    for (const auto& [residual, origin] : t.equations) rows_.push_back({residual, RowKind::Model, origin, {}, 0});
    return true;
  }

  /// Required rows first (cost 0), then the fixed = true of variables that
  /// are not states (cost 1: a flag on a variable that index reduction left
  /// without a state of its own, e.g. a body's velocity fixed beside the
  /// joint's, may over-determine the system; it then gives way), then the
  /// optional x = start (cost 2), last (cost 3) those of states the initial
  /// equations mention (x or der(x)): an initial equation about x is meant to
  /// determine x.
  std::vector<int> match() {
    std::unordered_set<Expr, ExprHash> mentioned;
    for (const InitialEquation& e : in_.equations)
      for (Expr l : leaves(a_, std::span(&e.residual, 1))) mentioned.insert(l);
    std::vector<std::vector<CostEdge>> edges;
    for (const Row& r : rows_) {
      std::vector<CostEdge> row;
      int cost = 0;
      if (r.kind == RowKind::FixedAlgebraic) cost = 1;
      if (r.kind == RowKind::StartGuess) {
        const OdeState& x = m_.states[r.state];
        cost = mentioned.contains(x.symbol) || mentioned.contains(x.derivative) ? 3 : 2;
      }
      for (Expr l : leaves(a_, std::span(&r.residual, 1)))
        if (auto it = local_.find(l); it != local_.end()) row.push_back({it->second, cost});
      edges.push_back(std::move(row));
    }
    return tiered_matching(edges, static_cast<int>(unknowns_.size()));
  }

  /// Every required row and every unknown matched, else a diagnostic.
  bool check(const std::vector<int>& col_of) {
    std::vector<const Row*> over;
    std::vector<const Row*> dropped;
    for (std::size_t r = 0; r < rows_.size(); ++r) {
      if (col_of[r] >= 0 || rows_[r].kind == RowKind::StartGuess) continue;
      (rows_[r].kind == RowKind::FixedAlgebraic ? dropped : over).push_back(&rows_[r]);
    }
    report_dropped(dropped);
    if (!over.empty()) {
      report_overdetermined(over);
      return false;
    }
    std::vector<bool> matched(unknowns_.size(), false);
    for (int c : col_of)
      if (c >= 0) matched[static_cast<std::size_t>(c)] = true;
    std::string missing;
    for (std::size_t j = 0; j < unknowns_.size(); ++j)
      if (!matched[j]) missing += (missing.empty() ? "" : ", ") + a_.symbol_info(unknowns_[j]).name;
    if (missing.empty()) return true;
    diags_.report(DiagId::StructurallySingular, first_initial_range(),
                  "the initial system is singular: no equation determines " + missing);
    return false;
  }

  frontend::SourceRange first_initial_range() const {
    return in_.equations.empty() ? frontend::SourceRange{} : in_.equations.front().range;
  }

  void report_overdetermined(const std::vector<const Row*>& over) {
    const Row& first = *over.front();
    const frontend::SourceRange at = first.range.valid() ? first.range : first_initial_range();
    diags_.report(DiagId::InitialOverdetermined, at,
                  fmt::format("the initial system is over-determined: {} equation{} more than the "
                              "unknowns at t0 allow; with the others, this one has no unknown left: {}",
                              over.size(), over.size() == 1 ? "" : "s", first.origin));
    for (std::size_t i = 1; i < over.size() && i < 10; ++i)
      diags_.note(over[i]->range, "also left without an unknown: " + over[i]->origin);
    std::string fixed;
    for (const OdeState& x : m_.states)
      if (x.fixed) fixed += (fixed.empty() ? "" : ", ") + x.info.name;
    if (!fixed.empty())
      diags_.note(at, "states declared fixed = true (each adds x = start): " + fixed);
  }

  /// The fixed = true flags of variables that are not states which the
  /// system could not admit beside the required rows.
  void report_dropped(const std::vector<const Row*>& dropped) {
    if (dropped.empty()) return;
    std::string names;
    for (std::size_t i = 0; i < dropped.size() && i < 10; ++i) {
      const std::string& o = dropped[i]->origin;
      names += (i ? ", " : "") + o.substr(0, o.find(" = its start value"));
    }
    if (dropped.size() > 10) names += fmt::format(", ... ({} variables)", dropped.size());
    diags_.report(DiagId::InitialStartFixed, first_initial_range(),
                  fmt::format("{} variable(s) declared fixed = true are not states and the initial system, "
                              "with the states' fixed values and the initial equations, leaves them no "
                              "unknown: their start values are not imposed: {}",
                              dropped.size(), names));
  }

  /// OpenModelica's note for an under-determined initial system (not
  /// without initial equations: the states then start at their start values
  /// as in any simulation).
  void warn_free_states(const std::vector<int>& col_of) {
    if (in_.equations.empty()) return;
    std::string names;
    std::size_t n = 0;
    for (std::size_t r = 0; r < rows_.size(); ++r)
      if (rows_[r].kind == RowKind::StartGuess && col_of[r] >= 0) {
        if (n++ < 10) names += (names.empty() ? "" : ", ") + m_.states[rows_[r].state].info.name;
      }
    if (n == 0) return;
    if (n > 10) names += fmt::format(", ... ({} states)", n);
    diags_.report(DiagId::InitialStartFixed, first_initial_range(),
                  "the initial equations leave " + std::to_string(n) +
                      " state(s) free; they start at their start values: " + names);
  }

  void solve(const std::vector<int>& col_of) {
    std::vector<int> kept;
    std::vector<std::vector<int>> lists;
    for (std::size_t r = 0; r < rows_.size(); ++r) {
      if (col_of[r] < 0) continue;
      kept.push_back(static_cast<int>(r));
      std::vector<int> row;
      for (Expr l : leaves(a_, std::span(&rows_[r].residual, 1)))
        if (auto it = local_.find(l); it != local_.end()) row.push_back(it->second);
      lists.push_back(std::move(row));
    }
    const Incidence g = Incidence::from_lists(static_cast<int>(unknowns_.size()), lists);
    Matching m;
    m.unknown_of.resize(kept.size());
    m.equation_of.assign(unknowns_.size(), -1);
    for (std::size_t i = 0; i < kept.size(); ++i) {
      m.unknown_of[i] = col_of[static_cast<std::size_t>(kept[i])];
      m.equation_of[static_cast<std::size_t>(m.unknown_of[i])] = static_cast<int>(i);
    }
    m.size = static_cast<int>(kept.size());
    for (const auto& blk : blt_blocks(g, m)) block(blk, kept, m);
    for (OdeState& x : m_.states) x.start = values_.at(x.symbol);
  }

  /// Solves one BLT block over the original symbols, then expresses it in
  /// the values found so far: a closed form, or a step over fresh symbols.
  void block(const std::vector<int>& blk, const std::vector<int>& kept, const Matching& m) {
    BlockEquations eqs;
    for (int i : blk) {
      const Row& r = rows_[static_cast<std::size_t>(kept[static_cast<std::size_t>(i)])];
      eqs.residuals.push_back(r.residual);
      eqs.origins.push_back(r.origin);
      const auto j = static_cast<std::size_t>(m.unknown_of[static_cast<std::size_t>(i)]);
      eqs.unknowns.push_back(unknowns_[j]);
      eqs.start.push_back(guess_[j]);
      eqs.start_guess.push_back(in_.start_guess.count(unknowns_[j]) ? 1 : 0);
    }
    std::vector<Step> steps = solve_block_torn(a_, eqs, at_start(), in_.tearing);
    for (Step& step : steps) add(step);
  }

  /// Every unknown at its guess, parameters at their values, t = 0, u = 0.
  const LeafValues& at_start() {
    if (!at_start_.empty()) return at_start_;
    for (std::size_t j = 0; j < unknowns_.size(); ++j) at_start_[unknowns_[j]] = guess_[j];
    for (const OdeParameter& p : m_.parameters) at_start_[p.symbol] = p.value;
    for (const OdeInput& u : m_.inputs) at_start_[u.symbol] = 0.0;
    for (const OdeDiscrete& d : m_.discrete) {
      at_start_[d.symbol] = d.start;
      at_start_[a_.pre(d.symbol)] = d.start;
    }
    at_start_[m_.time] = 0.0;
    return at_start_;
  }

  /// Expresses one step of a block in the values found so far: a closed
  /// form, or a step over fresh symbols.
  void add(Step& step) {
    if (auto* as = std::get_if<Assignment>(&step)) {
      Expr value = substitute(a_, as->value, values_);
      // The values so far fold its equation to 0/0 (SaturatingInductor's
      // (L - Linf)*i/Ipar = (Lzer - Linf)*atan(i/Ipar) at i = 0): the
      // equation holds for any value here, so the variable keeps its guess.
      if (a_.is_constant(value) && std::isnan(a_.constant_value(value))) {
        const double guess = guess_[static_cast<std::size_t>(local_.at(as->target))];
        diags_.report(DiagId::InitialStartFixed, first_initial_range(),
                      fmt::format("'{}' is left undetermined at the initial point: its equation ({}) gives "
                                  "0/0 there, so it starts at its start value {}",
                                  a_.symbol_info(as->target).name, as->origin, guess));
        value = a_.constant(guess);
      }
      values_[as->target] = value;
      return;
    }
    auto& b = std::get<EquationBlock>(step);
    ExprMap renamed = values_;
    for (Expr& z : b.unknowns) {
      const std::string name = "$init(" + a_.symbol_info(z).name + ")";
      const Expr fresh = a_.symbol(name, SymbolRole::Algebraic,
                                   static_cast<std::int32_t>(m_.initial_unknowns.size()));
      VariableInfo info;
      info.name = name;
      if (const auto it = info_.find(z); it != info_.end()) info = *it->second, info.name = name;
      m_.initial_unknowns.push_back({info, fresh});
      renamed[z] = fresh;
      values_[z] = fresh;
      z = fresh;
    }
    std::vector<Expr*> targets;
    for (Expr& r : b.residuals) targets.push_back(&r);
    for (Expr& o : b.offset) targets.push_back(&o);
    for (BlockEntry& e : b.jacobian) targets.push_back(&e.value);
    substitute_in_place(a_, targets, renamed);
    m_.initial_steps.push_back(std::move(step));
  }

  OdeModel& m_;
  ExprArena& a_;
  const InitialInput& in_;
  frontend::DiagnosticEngine& diags_;
  std::vector<Expr> unknowns_;
  std::vector<double> guess_;
  std::unordered_map<Expr, int, ExprHash> local_;
  std::vector<Row> rows_;
  ExprMap values_;  ///< unknown → its value (closed form or a fresh block symbol)
  LeafValues at_start_;  ///< tearing's start point, made on first use
  std::unordered_map<Expr, const VariableInfo*, ExprHash> info_ = [this] {
    std::unordered_map<Expr, const VariableInfo*, ExprHash> out;
    for (const OdeAlgebraic& y : m_.algebraics) out.emplace(y.symbol, &y.info);
    for (const OdeState& x : m_.states) out.emplace(x.symbol, &x.info);
    return out;
  }();
};

}  // namespace

bool lower_initial_system(OdeModel& model, const InitialInput& input,
                          frontend::DiagnosticEngine& diags) {
  // fixed = true on a variable that is not a state (e.g. a mass's position
  // when the relative position of a spring was chosen as the state) is an
  // initial condition too: it replaces one state's start value.
  if (input.equations.empty() && input.fixed_algebraics.empty()) return true;
  return InitialSystem(model, input, diags).run();
}

}  // namespace mo::symbolic::detail
