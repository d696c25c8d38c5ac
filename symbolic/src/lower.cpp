// The lowering pipeline; see lower.hpp.
#include "mo/symbolic/lower.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "alias.hpp"
#include "dae_build.hpp"
#include "index_reduction.hpp"
#include "initial_system.hpp"
#include "preferred_states.hpp"
#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/structure.hpp"
#include "mo/symbolic/substitute.hpp"
#include "solve.hpp"
#include "tearing.hpp"

namespace mo::symbolic {

using namespace detail;
using frontend::DiagId;

namespace {

std::size_t at(int i) { return static_cast<std::size_t>(i); }

/// The unknowns of the index-1 system and the live equations, renumbered.
struct System {
  std::vector<int> eqs;         ///< live DaeEq indices
  std::vector<int> unknowns;    ///< DaeVar indices that are not states
  std::vector<int> local;       ///< DaeVar → index in `unknowns`, or none
  Incidence incidence;
};

System make_system(const Dae& dae, const std::vector<bool>& state) {
  System s;
  s.local.assign(dae.vars.size(), none);
  for (std::size_t v = 0; v < dae.vars.size(); ++v)
    if (!dae.vars[v].eliminated && !state[v]) {
      s.local[v] = static_cast<int>(s.unknowns.size());
      s.unknowns.push_back(static_cast<int>(v));
    }
  const auto inc = incidence(dae);
  std::vector<std::vector<int>> rows;
  for (std::size_t e = 0; e < dae.eqs.size(); ++e) {
    if (dae.eqs[e].removed) continue;
    s.eqs.push_back(static_cast<int>(e));
    std::vector<int> row;
    for (int v : inc[e])
      if (s.local[at(v)] != none) row.push_back(s.local[at(v)]);
    rows.push_back(std::move(row));
  }
  s.incidence = Incidence::from_lists(static_cast<int>(s.unknowns.size()), rows);
  return s;
}

/// Reports unmatched equations (over-determined) and unknowns (under-determined).
void report_unmatched(const Dae& dae, const System& s, const Matching& m,
                      frontend::DiagnosticEngine& diags) {
  std::vector<int> eqs, vars;
  for (std::size_t i = 0; i < s.eqs.size(); ++i)
    if (m.unknown_of[i] == none) eqs.push_back(s.eqs[i]);
  for (std::size_t j = 0; j < s.unknowns.size(); ++j)
    if (m.equation_of[j] == none) vars.push_back(s.unknowns[j]);
  report_singular(dae, eqs, vars, diags);
}

/// Every variable's start value at the default parameters (0 where unset or
/// not computable), evaluated in one pass.
std::vector<double> start_values(const Dae& dae) {
  LeafValues values;
  for (const auto& p : dae.parameters) values[p.symbol] = p.value;
  std::vector<double> out(dae.vars.size(), 0.0);
  for (std::size_t v = 0; v < dae.vars.size(); ++v) {
    const Expr s = dae.vars[v].start;
    if (!s.valid() || dae.arena.is_constant(s)) {
      out[v] = s.valid() ? dae.arena.constant_value(s) : 0.0;
      continue;
    }
    try {
      out[v] = evaluate(dae.arena, std::span(&s, 1), values)[0];
    } catch (const std::invalid_argument&) {
    }
  }
  return out;
}

/// Builds the OdeModel: final symbols with their roles, steps from the BLT.
class Assembler {
public:
  Assembler(Dae& dae, const std::vector<bool>& state, const System& sys, const Matching& m,
            frontend::DiagnosticEngine& diags, bool tear)
      : dae_(dae), state_(state), sys_(sys), m_(m), diags_(diags), sources_(diags.sources()),
        tear_(tear) {}

  OdeModel run(const std::vector<std::vector<int>>& blocks) {
    OdeModel out;
    out.name = dae_.name;
    out.time = dae_.time;
    symbols(out);
    std::vector<Expr*> residuals;
    for (int e : sys_.eqs) residuals.push_back(&dae_.eqs[at(e)].residual);
    substitute_in_place(a(), residuals, map_);
    start_values_ = start_values(dae_);
    at_start_ = values_at_start(out);
    for (const auto& blk : blocks) block(out, blk);
    finish(out);
    InitialInput init = initial_input();
    out.arena = std::move(dae_.arena);
    lower_initial_system(out, init, diags_);
    return out;
  }

private:
  ExprArena& a() { return dae_.arena; }

  void symbols(OdeModel& out) {
    for (std::size_t v = 0; v < dae_.vars.size(); ++v) {
      if (!state_[v]) continue;
      const DaeVar& d = dae_.vars[v];
      OdeState s;
      s.info = d.info;
      // A derivative kept as a state (der(x) of a second-order model with no
      // velocity variable) must not clash with der(x) of the state x.
      if (d.integral != none && d.info.name.starts_with("der(")) s.info.name = "$" + s.info.name;
      const auto k = static_cast<std::int32_t>(out.states.size());
      s.symbol = a().symbol(s.info.name, SymbolRole::State, k);
      s.derivative = a().symbol("der(" + s.info.name + ")", SymbolRole::Derivative, k);
      s.start = d.start.valid() ? d.start : a().constant(0.0);
      s.fixed = d.fixed;
      map_[d.symbol] = s.symbol;
      state_of_[v] = out.states.size();
      state_vars_.push_back(static_cast<int>(v));
      out.states.push_back(s);
    }
    for (std::size_t i = 0; i < out.states.size(); ++i) derivative_symbol(out, i);
    for (int v : sys_.unknowns) {
      if (map_.contains(dae_.vars[at(v)].symbol)) continue;
      const DaeVar& d = dae_.vars[at(v)];
      const auto k = static_cast<std::int32_t>(out.algebraics.size());
      const Expr s = a().symbol(d.info.name, SymbolRole::Algebraic, k);
      map_[d.symbol] = s;
      out.algebraics.push_back({d.info, s});
    }
  }

  /// The state's derivative variable is either solved for (it becomes the
  /// Derivative symbol) or is itself a state (then der(x) := that state).
  void derivative_symbol(OdeModel& out, std::size_t i) {
    const int x = state_vars_[i];
    const int d = dae_.vars[at(x)].derivative;
    const DaeVar& dv = dae_.vars[at(d)];
    if (state_[at(d)]) {
      out.steps.emplace_back(Assignment{out.states[i].derivative, map_.at(dv.symbol)});
      return;
    }
    map_[dv.symbol] = out.states[i].derivative;
    if (!dv.info.name.starts_with("der("))
      out.eliminated.push_back({dv.info, out.states[i].derivative});
  }

  /// Every final symbol at its start value (parameters at their values,
  /// time and inputs 0): where tearing tests its choice (tearing.hpp).
  LeafValues values_at_start(const OdeModel& out) {
    LeafValues env;
    for (std::size_t v = 0; v < dae_.vars.size(); ++v)
      if (const auto it = map_.find(dae_.vars[v].symbol); it != map_.end() && a().is_leaf(it->second))
        env[it->second] = start_values_[v];
    for (const OdeParameter& p : dae_.parameters) env[p.symbol] = p.value;
    for (const OdeInput& u : dae_.inputs) env[u.symbol] = 0.0;
    for (const OdeDiscrete& d : dae_.discrete) {
      env[d.symbol] = d.start;
      env[a().pre(d.symbol)] = d.start;
    }
    env[out.time] = 0.0;
    return env;
  }

  void block(OdeModel& out, const std::vector<int>& blk) {
    BlockEquations eqs;
    for (int i : blk) {
      const DaeEq& e = dae_.eqs[at(sys_.eqs[at(i)])];
      eqs.residuals.push_back(e.residual);
      eqs.origins.push_back(origin(e.range));
      const int var = sys_.unknowns[at(m_.unknown_of[at(i)])];
      eqs.unknowns.push_back(map_.at(dae_.vars[at(var)].symbol));
      eqs.start.push_back(start_values_[at(var)]);
      eqs.start_guess.push_back(dae_.vars[at(var)].start_guess ? 1 : 0);
    }
    std::vector<Step> steps = solve_block_torn(a(), eqs, at_start_, tear_);
    if (const auto* b = std::get_if<EquationBlock>(&steps.front()); b && b->linear && constant_singular(*b))
      report_singular_block(blk);
    for (Step& s : steps) out.steps.push_back(std::move(s));
  }

  /// True if every coefficient of the linear block is a constant and the
  /// matrix is singular: no value of the model's parameters or time can make
  /// it solvable (equations inconsistent or redundant, `x + y = 1; x + y = 2`).
  bool constant_singular(const EquationBlock& b) const {
    const std::size_t n = b.unknowns.size();
    std::vector<double> m(n * n, 0.0);
    for (const BlockEntry& e : b.jacobian) {
      if (!dae_.arena.is_constant(e.value)) return false;
      m[e.row * n + e.col] = dae_.arena.constant_value(e.value);
    }
    for (std::size_t k = 0; k < n; ++k) {  // Gaussian elimination, partial pivoting
      std::size_t piv = k;
      for (std::size_t i = k + 1; i < n; ++i)
        if (std::fabs(m[i * n + k]) > std::fabs(m[piv * n + k])) piv = i;
      if (std::fabs(m[piv * n + k]) <= 1e-12) return true;
      for (std::size_t j = 0; j < n; ++j) std::swap(m[k * n + j], m[piv * n + j]);
      for (std::size_t i = k + 1; i < n; ++i) {
        const double f = m[i * n + k] / m[k * n + k];
        for (std::size_t j = k; j < n; ++j) m[i * n + j] -= f * m[k * n + j];
      }
    }
    return false;
  }

  void report_singular_block(const std::vector<int>& blk) {
    const auto& first = dae_.eqs[at(sys_.eqs[at(blk.front())])];
    diags_.report(frontend::DiagId::StructurallySingular, first.range,
                  blk.size() == 1
                      ? std::string("this equation is singular: the coefficient of its unknown is a "
                                    "constant 0 once the equations before it are used, so it is "
                                    "inconsistent with them or redundant")
                      : fmt::format("these {} equations are singular: their coefficients are "
                                    "constants and linearly dependent, so they are inconsistent "
                                    "or redundant",
                                    blk.size()));
    for (std::size_t i = 1; i < blk.size() && i < 10; ++i)
      diags_.note(dae_.eqs[at(sys_.eqs[at(blk[i])])].range, "one of the dependent equations");
  }

  /// "file.mo:12:3: <the source line, trimmed>" for the equation at `r`; empty without a range.
  std::string origin(frontend::SourceRange r) const {
    if (!r.valid()) return {};
    try {
      const frontend::LineColumn lc = sources_.position(r.file, r.begin);
      std::string line(sources_.line_text(r.file, r.begin));
      const auto first = line.find_first_not_of(" \t");
      line = first == std::string::npos ? "" : line.substr(first, 200);
      return fmt::format("{}:{}:{}: {}", sources_.name(r.file), lc.line, lc.column, line);
    } catch (const std::logic_error&) {
      return {};  // a range from another SourceManager (models built in code)
    }
  }

  void finish(OdeModel& out) {
    out.inputs = dae_.inputs;
    out.parameters = dae_.parameters;
    out.discrete = dae_.discrete;
    out.initial_flag = dae_.initial_flag;
    out.samples = dae_.samples;
    out.outputs.insert(out.outputs.end(), dae_.outputs.begin(), dae_.outputs.end());
    out.eliminated.insert(out.eliminated.end(), dae_.eliminated.begin(), dae_.eliminated.end());
    for (const DaeWhen& w : dae_.whens) {
      WhenClause c{w.condition, w.every_event, w.assignments, {}, w.terminates, w.terminate_message,
                   w.group, w.branch, w.prioritised};
      for (const auto& [v, e] : w.reinits)
        if (state_of_.contains(at(v))) c.reinits.push_back({state_of_.at(at(v)), e});
      out.whens.push_back(std::move(c));
    }
    std::vector<Expr*> targets;
    for (auto& s : out.states) targets.push_back(&s.start);
    for (auto& y : out.outputs) targets.push_back(&y.value);
    for (auto& e : out.eliminated) targets.push_back(&e.value);
    for (auto& s : out.samples) targets.push_back(&s.start);  // a computed parameter: its state
    for (auto& w : out.whens) {
      targets.push_back(&w.condition);
      for (auto& s : w.assignments) targets.push_back(&s.value);
      for (auto& r : w.reinits) targets.push_back(&r.value);
    }
    substitute_in_place(a(), targets, map_);
    std::vector<Expr> roots;
    for (const Step& s : out.steps) {
      if (const auto* as = std::get_if<Assignment>(&s)) roots.push_back(as->value);
      else for (Expr r : std::get<EquationBlock>(s).residuals) roots.push_back(r);
    }
    std::vector<Expr> in_steps;
    collect_zero_crossings(a(), roots, in_steps);
    for (const auto& w : out.whens) {
      roots.push_back(w.condition);
      if (w.every_event)  // a change of its relations between events is an event
        for (const auto& s : w.assignments) roots.push_back(s.value);
    }
    collect_zero_crossings(a(), roots, out.zero_crossings);
    for (Expr g : out.zero_crossings)
      out.zero_crossing_in_steps.push_back(std::find(in_steps.begin(), in_steps.end(), g) != in_steps.end());
  }

  /// The initial equations, fixed algebraic variables and Newton guesses over
  /// the final symbols (initial_system.hpp).
  InitialInput initial_input() {
    InitialInput in;
    in.tearing = tear_;
    initial_derivatives(in);
    std::vector<Expr*> targets;
    for (DaeEq& e : dae_.initial_eqs) targets.push_back(&e.residual);
    substitute_in_place(a(), targets, map_);
    for (const DaeEq& e : dae_.initial_eqs) in.equations.push_back({e.residual, e.range, origin(e.range)});
    for (std::size_t v = 0; v < dae_.vars.size(); ++v) {
      const DaeVar& d = dae_.vars[v];
      const auto it = map_.find(d.symbol);
      if (d.eliminated || it == map_.end()) continue;
      in.guess[it->second] = start_values_[v];
      if (d.start_guess) in.start_guess.insert(it->second);
      // fixed = true on a variable that is not a state is an initial
      // equation; so on a state's derivative (the MSL's Inertia
      // `a(fixed = true)`: a = der(w) became w's derivative variable).
      const SymbolRole role = a().symbol_info(it->second).role;
      if (d.fixed && !state_[v] && (role == SymbolRole::Algebraic || role == SymbolRole::Derivative))
        in.fixed_algebraics.emplace_back(it->second, substitute(a(), d.start, map_));
    }
    return in;
  }

  /// der(v) of the initial equations for v the model does not differentiate:
  /// the derivative index reduction made, if any, else defined by the
  /// initial system from v's value (a variable or an eliminated alias).
  void initial_derivatives(InitialInput& in) {
    for (const InitialDerivative& d : dae_.initial_derivatives) {
      const DaeVar& v = dae_.vars[at(d.var)];
      if (v.derivative != none) {
        if (const auto it = map_.find(dae_.vars[at(v.derivative)].symbol); it != map_.end()) {
          map_[d.symbol] = it->second;
          continue;
        }
      }
      if (!v.eliminated) {
        in.time_derivatives.emplace_back(d.symbol, map_.at(v.symbol));
        continue;
      }
      const auto it = std::find_if(dae_.eliminated.begin(), dae_.eliminated.end(),
                                   [&](const OdeOutput& e) { return e.info.name == v.info.name; });
      if (it != dae_.eliminated.end())
        in.time_derivatives.emplace_back(d.symbol, substitute(a(), it->value, map_));
    }
  }

  Dae& dae_;
  const std::vector<bool>& state_;
  const System& sys_;
  const Matching& m_;
  ExprMap map_;  ///< internal symbol → final symbol
  std::unordered_map<std::size_t, std::size_t> state_of_;  ///< DaeVar → state index
  std::vector<int> state_vars_;  ///< state index → DaeVar
  std::vector<double> start_values_;  ///< per DaeVar
  LeafValues at_start_;  ///< final symbols at their start values
  frontend::DiagnosticEngine& diags_;
  const frontend::SourceManager& sources_;
  bool tear_;  ///< tear nonlinear blocks (LowerOptions::tearing)
};

/// Expression text with the internal name marker removed (for traces).
std::string text(const ExprArena& a, Expr e) {
  std::string t = to_modelica(a, e), out;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] == '\'' && i + 1 < t.size() && t[i + 1] == '?') {  // '?name' → `name`
      const std::size_t end = t.find('\'', i + 2);
      out += "`" + t.substr(i + 2, end - i - 2) + "`";
      i = end;
      continue;
    }
    out += t[i];
  }
  return out;
}

void trace_alias(const Dae& dae, std::string& out) {
  out += "== alias ==\n";
  for (const auto& e : dae.eliminated)
    out += "  " + e.info.name + " = " + text(dae.arena, e.value) + "\n";
}

void trace_index(const Dae& dae, std::size_t first_new, const std::vector<bool>& state,
                 std::string& out) {
  out += "== index reduction ==\n";
  for (std::size_t e = first_new; e < dae.eqs.size(); ++e)
    out += fmt::format("  differentiated: 0 = {}\n", text(dae.arena, dae.eqs[e].residual));
  for (std::size_t v = 0; v < dae.vars.size(); ++v) {
    const DaeVar& d = dae.vars[v];
    if (d.eliminated || d.derivative == none) continue;
    out += fmt::format("  {}: {}\n", state[v] ? "state" : "dummy", d.info.name);
  }
}

void trace_blt(const Dae& dae, const System& sys, const Matching& m,
               const std::vector<std::vector<int>>& blocks, std::string& out) {
  out += "== blt ==\n";
  for (const auto& blk : blocks) {
    out += fmt::format("  block of {}:", blk.size());
    for (int i : blk)
      out += " " + dae.vars[at(sys.unknowns[at(m.unknown_of[at(i)])])].info.name;
    out += "\n";
    for (int i : blk)
      out += "    0 = " + text(dae.arena, dae.eqs[at(sys.eqs[at(i)])].residual) + "\n";
  }
}

}  // namespace

std::optional<OdeModel> lower(const frontend::flat::Model& flat,
                              frontend::DiagnosticEngine& diags, const LowerOptions& options,
                              LowerStats* stats) {
  std::optional<Dae> dae = build_dae(flat, diags);
  if (!dae) return std::nullopt;
  LowerStats st;
  st.aliases = eliminate_aliases(*dae).eliminated;
  if (options.trace) trace_alias(*dae, *options.trace);
  mark_source_derivatives(*dae);
  const std::size_t before = dae->eqs.size();
  const std::optional<std::vector<bool>> selected = reduce_index(*dae, diags);
  if (!selected) return std::nullopt;
  const std::vector<bool>& state = *selected;
  st.differentiated = dae->eqs.size() - before;
  for (std::size_t v = 0; v < dae->vars.size(); ++v)
    if (!dae->vars[v].eliminated && dae->vars[v].derivative != none && !state[v])
      ++st.dummy_derivatives;
  if (options.trace) trace_index(*dae, before, state, *options.trace);
  const System sys = make_system(*dae, state);
  st.equations = sys.eqs.size();
  const Matching m = maximum_matching(sys.incidence);
  if (m.size != static_cast<int>(sys.eqs.size()) ||
      m.size != static_cast<int>(sys.unknowns.size())) {
    report_unmatched(*dae, sys, m, diags);
    return std::nullopt;
  }
  const auto blocks = blt_blocks(sys.incidence, m);
  if (options.trace) trace_blt(*dae, sys, m, blocks, *options.trace);
  if (stats) *stats = st;
  const unsigned errors = diags.error_count();
  OdeModel out = Assembler(*dae, state, sys, m, diags, options.tearing).run(blocks);
  if (diags.error_count() > errors) return std::nullopt;
  return out;
}

}  // namespace mo::symbolic
