// The stacked multi-phase model; see study_phases.hpp.
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <unordered_map>

#include "mo/symbolic/event_tangents.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/traversal.hpp"
#include "study_phases.hpp"

namespace mo::tools {

using symbolic::Expr;
using symbolic::ExprArena;
using symbolic::ExprKind;
using symbolic::OdeModel;
using symbolic::SymbolRole;

namespace {

/// Copies expressions of one arena into another, leaves (and chosen nodes)
/// replaced by given expressions of the destination.
class Copier {
public:
  Copier(const ExprArena& src, ExprArena& dst) : src_(src), dst_(dst) {}
  void set(Expr src_node, Expr value) { fixed_[src_node] = value; }
  /// Copies every node under `roots` (one traversal); then at() gives them.
  void copy_all(const std::vector<Expr>& roots) {
    for (Expr e : symbolic::topological_order(src_, roots)) {
      if (memo_.contains(e)) continue;
      if (auto f = fixed_.find(e); f != fixed_.end()) {
        memo_.emplace(e, f->second);
        continue;
      }
      const ExprKind k = src_.kind(e);
      if (k == ExprKind::Constant) {
        memo_.emplace(e, dst_.constant(src_.constant_value(e)));
        continue;
      }
      if (src_.is_leaf(e))
        throw std::logic_error("multi-phase model: no value for " + symbolic::to_modelica(src_, e));
      std::vector<Expr> ops;
      for (std::size_t i = 0; i < symbolic::arity(k); ++i) ops.push_back(memo_.at(src_.operand(e, i)));
      memo_.emplace(e, dst_.make(k, ops));
    }
  }
  [[nodiscard]] Expr at(Expr e) const { return memo_.at(e); }
  Expr copy(Expr e) {
    copy_all({e});
    return at(e);
  }

private:
  const ExprArena& src_;
  ExprArena& dst_;
  symbolic::ExprMap fixed_, memo_;
};

std::string phase_name(std::size_t k, const std::string& name) {
  return "phase" + std::to_string(k + 1) + "." + name;
}

}  // namespace

namespace {

/// Builds the phases into `out` step by step.
class PhaseBuilder {
public:
  PhaseBuilder(OdeModel& base, const RelationMap& rel, const ModeSequence& seq, const PhaseLayout& layout,
               PhasedModel& out)
      : b_(base), rel_(rel), seq_(seq), lay_(layout), out_(out), m_(out.ode), K_(layout.mode.size()) {}

  void build(double t0, double tf, std::optional<std::size_t> lagrange) {
    m_.name = b_.name;
    m_.time = m_.arena.symbol(b_.arena.symbol_info(b_.time).name, SymbolRole::Time,
                              b_.arena.symbol_info(b_.time).index);
    out_.phases = K_;
    out_.layout = lay_;
    out_.nx = b_.states.size(), out_.nu = b_.inputs.size(), out_.np = b_.parameters.size();
    out_.ny = b_.outputs.size();
    if (b_.num_base_states() < b_.states.size()) tangents_ = symbolic::event_tangents(b_);
    add_parameters();
    taus_.push_back(m_.arena.constant(t0));
    for (const auto& b : lay_.boundaries) {
      const auto sw = b.switch_index;
      taus_.push_back(!sw                                     ? m_.arena.constant(b.time)
                      : out_.tick_time[*sw].valid()           ? out_.tick_time[*sw]
                      : !seq_.switches[*sw].timed             ? m_.parameters[out_.switch_time[*sw]].symbol
                                                              : m_.arena.constant(b.time));
    }
    taus_.push_back(m_.arena.constant(tf));
    add_variables();
    add_held();
    for (std::size_t k = 0; k < K_; ++k) add_phase(k);
    add_initial_held();
    for (std::size_t k = 0; k + 1 < K_; ++k) add_boundary(k);
    for (std::size_t k = 0; k < K_; ++k) add_sign_outputs(k);
    if (K_ > 1)
      for (std::size_t k = 0; k < K_; ++k) out_.length_output.push_back(add_output("$phase" + std::to_string(k + 1) + ".length", length(k)));
    if (lagrange) {
      Expr sum = m_.arena.constant(0.0);
      for (std::size_t k = 0; k < K_; ++k)
        sum = m_.arena.add(sum, m_.arena.mul(length(k), m_.outputs[out_.output(k, *lagrange)].value));
      out_.lagrange_output = add_output("$phases.objective_integrand", sum);
    }
  }

private:
  Expr length(std::size_t k) { return m_.arena.sub(taus_[k + 1], taus_[k]); }

  std::size_t add_parameter(const symbolic::VariableInfo& info, double value) {
    const std::size_t index = m_.parameters.size();
    Expr s = m_.arena.symbol(info.name, SymbolRole::Parameter, static_cast<std::int32_t>(index));
    m_.parameters.push_back({info, s, value});
    return index;
  }

  void add_parameters() {
    for (const auto& p : b_.parameters) add_parameter(p.info, p.value);
    for (std::size_t k = 0; k < seq_.switches.size(); ++k) {
      symbolic::VariableInfo info;
      info.name = "$switch" + std::to_string(k + 1) + ".time";
      out_.switch_time.push_back(add_parameter(info, seq_.switches[k].time));
      out_.timed_switch.push_back(seq_.switches[k].timed);
      out_.tick_time.push_back(tick_time(seq_.switches[k]));
    }
    if (tangents_)
      for (std::size_t k = 0; k < seq_.switches.size(); ++k) {
        out_.fplus_parameter.push_back(m_.parameters.size());
        for (std::size_t i = 0; i < b_.num_base_states(); ++i) {
          symbolic::VariableInfo info;
          info.name = "$switch" + std::to_string(k + 1) + ".fplus." + b_.states[i].info.name;
          add_parameter(info, 0.0);
        }
        out_.input_parameter.push_back(m_.parameters.size());
        for (const auto& u : b_.inputs) {
          symbolic::VariableInfo info;
          info.name = "$switch" + std::to_string(k + 1) + ".input." + u.info.name;
          add_parameter(info, 0.0);
        }
      }
    for (std::size_t k = 0; k + 1 < K_; ++k) {
      out_.phase_start.push_back(m_.parameters.size());
      for (std::size_t i = 0; i < b_.states.size(); ++i) {
        symbolic::VariableInfo info = b_.states[i].info;
        info.name = phase_name(k + 1, b_.states[i].info.name) + ".start";
        const auto& after = lay_.boundaries[k].states_after;
        add_parameter(info, i < after.size() ? after[i] : 0.0);
      }
    }
  }

  /// States, their physical derivatives (algebraic), inputs and algebraics per phase.
  void add_variables() {
    for (std::size_t k = 0; k < K_; ++k)
      for (std::size_t i = 0; i < b_.states.size(); ++i) {
        symbolic::OdeState s;
        s.info = b_.states[i].info;
        s.info.name = phase_name(k, b_.states[i].info.name);
        const auto idx = static_cast<std::int32_t>(m_.states.size());
        s.symbol = m_.arena.symbol(s.info.name, SymbolRole::State, idx);
        s.derivative = m_.arena.symbol("der(" + s.info.name + ")", SymbolRole::Derivative, idx);
        s.fixed = k > 0 || b_.states[i].fixed;
        m_.states.push_back(std::move(s));
      }
    for (std::size_t k = 0; k < K_; ++k)
      for (const auto& u : b_.inputs) {
        symbolic::OdeInput in{u.info, {}};
        in.info.name = phase_name(k, u.info.name);
        in.symbol = m_.arena.symbol(in.info.name, SymbolRole::Input, static_cast<std::int32_t>(m_.inputs.size()));
        m_.inputs.push_back(std::move(in));
      }
  }

  Expr add_algebraic(const symbolic::VariableInfo& info) {
    symbolic::OdeAlgebraic a{info, {}};
    a.symbol = m_.arena.symbol(info.name, SymbolRole::Algebraic, static_cast<std::int32_t>(m_.algebraics.size()));
    m_.algebraics.push_back(a);
    return a.symbol;
  }

  std::size_t add_output(const std::string& name, Expr value) {
    symbolic::OdeOutput y;
    y.info.name = name;
    y.value = value;
    m_.outputs.push_back(std::move(y));
    return m_.outputs.size() - 1;
  }

  /// τ = start + k·interval of a timed switch's tick over the parameters, or
  /// an invalid Expr.
  Expr tick_time(const PhaseSwitch& sw) {
    if (!sw.timed || !sw.tick) return {};
    const auto& smp = b_.samples[sw.tick->first];
    Copier c(b_.arena, m_.arena);
    for (std::size_t j = 0; j < b_.parameters.size(); ++j) c.set(b_.parameters[j].symbol, m_.parameters[j].symbol);
    return m_.arena.add(c.copy(smp.start), m_.arena.mul(m_.arena.constant(sw.tick->second), c.copy(smp.interval)));
  }

  /// The clauses that fire where phase k starts: at t0, or at the switch before it.
  std::vector<std::size_t> whens_at_start(std::size_t k) const {
    if (k == 0) return seq_.initial_whens;
    const auto& sw = lay_.boundaries[k - 1].switch_index;
    return sw ? seq_.switches[*sw].whens : std::vector<std::size_t>{};
  }

  /// Which discrete variables are unknowns of the phases: the held values
  /// and their discrete sensitivities (∂d/∂p, set with d).
  void mark_unknowns() {
    unknown_ = rel_.held;
    unknown_.resize(b_.discrete.size(), false);
    for (std::size_t i = 0; i < b_.discrete.size(); ++i)
      if (const auto& of = b_.discrete[i].sensitivity) {
        unknown_[i] = of->discrete < rel_.held.size() && rel_.held[of->discrete];
        sensitivity_of_[{of->discrete, of->parameter}] = i;
      }
  }

  /// The discrete variable that is ∂d_i/∂p_j, if d_i has one for p_j.
  std::optional<std::size_t> discrete_sensitivity(std::size_t i, std::size_t j) const {
    const auto it = sensitivity_of_.find({i, j});
    return it == sensitivity_of_.end() ? std::nullopt : std::optional<std::size_t>(it->second);
  }

  /// Per phase the held values (and their sensitivities): a new unknown
  /// where a clause sets one, the previous phase's otherwise (the
  /// simulation's value in the first phase).
  void add_held() {
    mark_unknowns();
    held_.assign(K_, std::vector<Expr>(b_.discrete.size()));
    for (std::size_t k = 0; k < K_; ++k) {
      const PhaseMode& mode = seq_.modes[lay_.mode[k]];
      std::vector<bool> set(b_.discrete.size(), false);
      for (std::size_t w : whens_at_start(k))
        for (const auto& a : b_.whens[w].assignments)
          for (std::size_t j = 0; j < b_.discrete.size(); ++j) set[j] = set[j] || b_.discrete[j].symbol == a.target;
      for (std::size_t j = 0; j < b_.discrete.size(); ++j)
        if (const auto& of = b_.discrete[j].sensitivity) set[j] = set[of->discrete];
      for (std::size_t j = 0; j < b_.discrete.size(); ++j) {
        if (!unknown_[j]) continue;
        const double value = j < mode.discrete.size() ? mode.discrete[j] : b_.discrete[j].start;
        if (!set[j]) {
          held_[k][j] = k == 0 ? m_.arena.constant(value) : held_[k - 1][j];
          continue;
        }
        symbolic::VariableInfo info = b_.discrete[j].info;
        info.name = phase_name(k, b_.discrete[j].info.name);
        out_.held_parameter.push_back(add_parameter(info, value));
        held_[k][j] = m_.parameters[out_.held_parameter.back()].symbol;
      }
    }
  }

  /// The held values the clauses fired at t0 set, at s = 0 of the first
  /// phase: pre() is the start value (check_initial_whens refuses what
  /// would need more). With sensitivity states, their sensitivities too:
  /// the value's tangent along (∂x0/∂p_j, e_j, 0), δd the start values.
  void add_initial_held() {
    const PhaseMode& mode = seq_.modes[lay_.mode[0]];
    for (std::size_t w : seq_.initial_whens)
      for (std::size_t n = 0; n < b_.whens[w].assignments.size(); ++n) {
        const auto& a = b_.whens[w].assignments[n];
        const auto j = held_index(a.target);
        if (!j) continue;
        const Expr value = phase_copy(0, mode, mode, {a.value}, nullptr, {}, true).front();
        out_.held_initial_output.push_back(
            add_output("$initial.held." + b_.discrete[*j].info.name, m_.arena.sub(value, held_[0][*j])));
        if (!tangents_) continue;
        for (const auto& [p, entries] : sensitivity_states()) {
          const auto sd = discrete_sensitivity(*j, p);
          if (!sd) continue;
          auto [dx, dp] = unit_direction(0, p, entries);
          const Expr dv = tangent_copy(0, mode, mode, dx, dp, m_.arena.constant(0.0),
                                       {tangents_->whens[w].assignments[n]}, p, true).front();
          out_.held_initial_output.push_back(
              add_output("$initial.held." + b_.discrete[*sd].info.name, m_.arena.sub(dv, held_[0][*sd])));
        }
      }
  }

  /// Per parameter j with sensitivity states: (base state i, its sensitivity state).
  std::map<std::size_t, std::vector<std::pair<std::size_t, std::size_t>>> sensitivity_states() const {
    std::map<std::size_t, std::vector<std::pair<std::size_t, std::size_t>>> out;
    for (std::size_t s = b_.num_base_states(); s < b_.states.size(); ++s)
      if (const auto& of = b_.states[s].sensitivity) out[of->parameter].push_back({of->state, s});
    return out;
  }

  /// The direction (S^k_j, e_j) of phase k's sensitivity states for parameter j.
  std::pair<std::vector<Expr>, std::vector<Expr>> unit_direction(
      std::size_t k, std::size_t j, const std::vector<std::pair<std::size_t, std::size_t>>& entries) {
    const Expr zero = m_.arena.constant(0.0);
    std::vector<Expr> dx(b_.states.size(), zero), dp(b_.parameters.size(), zero);
    for (const auto& [i, s] : entries) dx[i] = m_.states[out_.state(k, s)].symbol;
    dp[j] = m_.arena.constant(1.0);
    return {dx, dp};
  }

  /// The discrete sensitivities of the held values the clauses fired at
  /// switch `sw` (the end of phase k) set, along the directions `dirs`
  /// (per parameter: δx, δp, δt as the state jump takes them; δd = S_d^k).
  void add_held_sensitivities(std::size_t k, const PhaseSwitch& sw,
                              const std::map<std::size_t, std::tuple<std::vector<Expr>, std::vector<Expr>, Expr>>& dirs) {
    const PhaseMode& before = seq_.modes[lay_.mode[k]];
    const PhaseMode& next = seq_.modes[lay_.mode[k + 1]];
    for (std::size_t w : sw.whens)
      for (std::size_t n = 0; n < b_.whens[w].assignments.size(); ++n) {
        const auto j = held_index(b_.whens[w].assignments[n].target);
        if (!j) continue;
        for (const auto& [p, dir] : dirs) {
          const auto sd = discrete_sensitivity(*j, p);
          if (!sd) continue;
          const auto& [dx, dp, dt] = dir;
          const Expr dv = tangent_copy(k, next, before, dx, dp, dt, {tangents_->whens[w].assignments[n]}, p).front();
          const std::string name = "$boundary" + std::to_string(k + 1) + ".held." + b_.discrete[*sd].info.name;
          out_.held_output.push_back(add_output(name, m_.arena.sub(dv, held_[k + 1][*sd])));
        }
      }
  }

  std::optional<std::size_t> held_index(Expr target) const {
    for (std::size_t j = 0; j < b_.discrete.size(); ++j)
      if (rel_.held[j] && b_.discrete[j].symbol == target) return j;
    return std::nullopt;
  }

  /// Leaves of phase k: states, inputs, parameters, time, discrete values of
  /// `mode` (pre() those of `before`); held values of phase `held_now`
  /// (pre() of `held_before`), both k by default.
  void map_leaves(Copier& c, std::size_t k, const PhaseMode& mode, const PhaseMode& before,
                  std::optional<std::size_t> held_now = {}, std::optional<std::size_t> held_before = {}) {
    for (std::size_t i = 0; i < b_.states.size(); ++i) {
      c.set(b_.states[i].symbol, m_.states[out_.state(k, i)].symbol);
      c.set(b_.arena.pre(b_.states[i].symbol), m_.states[out_.state(k, i)].symbol);
    }
    for (std::size_t j = 0; j < b_.inputs.size(); ++j) c.set(b_.inputs[j].symbol, m_.inputs[out_.input(k, j)].symbol);
    for (std::size_t j = 0; j < b_.parameters.size(); ++j) c.set(b_.parameters[j].symbol, m_.parameters[j].symbol);
    c.set(b_.time, m_.arena.add(taus_[k], m_.arena.mul(m_.time, length(k))));
    for (std::size_t j = 0; j < b_.discrete.size(); ++j) {
      if (unknown_[j]) {
        c.set(b_.discrete[j].symbol, held_[held_now.value_or(k)][j]);
        c.set(b_.arena.pre(b_.discrete[j].symbol), held_[held_before.value_or(k)][j]);
        continue;
      }
      const double now = j < mode.discrete.size() ? mode.discrete[j] : b_.discrete[j].start;
      const double pre = j < before.discrete.size() ? before.discrete[j] : now;
      c.set(b_.discrete[j].symbol, m_.arena.constant(now));
      c.set(b_.arena.pre(b_.discrete[j].symbol), m_.arena.constant(pre));
    }
    for (const auto& e : rel_.entries) {
      const int sign = e.indicator < mode.signs.size() ? mode.signs[e.indicator] : 0;
      if (sign == 0) continue;  // never switched and never away from 0: evaluated as is
      c.set(e.relation, m_.arena.constant(sign < 0 ? e.value_if_down : 1.0 - e.value_if_down));
    }
  }

  void add_phase(std::size_t k) {
    const PhaseMode& mode = seq_.modes[lay_.mode[k]];
    Copier c(b_.arena, m_.arena);
    map_leaves(c, k, mode, mode);
    std::vector<Expr> physical_der;
    for (std::size_t i = 0; i < b_.states.size(); ++i) {
      symbolic::VariableInfo info = b_.states[i].info;
      info.name = phase_name(k, "der(" + b_.states[i].info.name + ")");
      physical_der.push_back(add_algebraic(info));
      c.set(b_.states[i].derivative, physical_der.back());
    }
    for (const auto& a : b_.algebraics) {
      symbolic::VariableInfo info = a.info;
      info.name = phase_name(k, a.info.name);
      c.set(a.symbol, add_algebraic(info));
    }
    std::vector<Expr> roots = b_.equation_expressions();
    for (const auto& s : b_.states) roots.push_back(s.start);
    for (const auto& s : b_.steps) {
      if (const auto* as = std::get_if<symbolic::Assignment>(&s))
        roots.push_back(as->target);
      else
        for (Expr u : std::get<symbolic::EquationBlock>(s).unknowns) roots.push_back(u);
    }
    c.copy_all(roots);
    for (const auto& s : b_.steps) copy_step(c, s);
    for (std::size_t i = 0; i < b_.states.size(); ++i) {
      auto& x = m_.states[out_.state(k, i)];
      x.start = k == 0 ? c.at(b_.states[i].start) : m_.parameters[out_.phase_start[k - 1] + i].symbol;
      m_.steps.push_back(symbolic::Assignment{x.derivative, m_.arena.mul(length(k), physical_der[i]), {}});
    }
    for (const auto& y : b_.outputs) {
      symbolic::OdeOutput copy = y;
      copy.info.name = phase_name(k, y.info.name);
      copy.value = c.at(y.value);
      m_.outputs.push_back(std::move(copy));
    }
  }

  /// Appends a copy of step `s` with its expressions copied by `c`.
  void copy_step(Copier& c, const symbolic::Step& s) {
    if (const auto* as = std::get_if<symbolic::Assignment>(&s)) {
      m_.steps.emplace_back(symbolic::Assignment{c.at(as->target), c.at(as->value), as->origin});
      return;
    }
    auto& b = std::get<symbolic::EquationBlock>(m_.steps.emplace_back(std::get<symbolic::EquationBlock>(s)));
    for (Expr& e : b.unknowns) e = c.at(e);
    for (Expr& e : b.residuals) e = c.at(e);
    for (Expr& e : b.offset) e = c.at(e);
    for (auto& e : b.jacobian) e.value = c.at(e.value);
  }

  /// Outputs at the end of phase k: at a switch the indicator, and per state
  /// r(x^k) − x^{k+1}(0) (r the identity at a fixed cut or without reinit).
  void add_boundary(std::size_t k) {
    const PhaseBoundary& bd = lay_.boundaries[k];
    const PhaseMode& before = seq_.modes[lay_.mode[k]];
    const PhaseMode& after_mode = seq_.modes[lay_.mode[k + 1]];
    const std::string prefix = "$boundary" + std::to_string(k + 1);
    std::vector<Expr> after;
    for (std::size_t i = 0; i < b_.states.size(); ++i) after.push_back(m_.states[out_.state(k, i)].symbol);
    if (bd.switch_index) {
      const PhaseSwitch& sw = seq_.switches[*bd.switch_index];
      if (!sw.timed) {
        Copier c(b_.arena, m_.arena);
        map_leaves(c, k, before, before);
        map_algebraics(c, k);
        out_.indicator_output.push_back(add_output(prefix + ".indicator", c.copy(b_.zero_crossings[sw.indicator])));
      }
      add_held_values(k, sw);
      Copier c(b_.arena, m_.arena);  // the jump: d new, pre(d) old, pre(x) = x^k(1)
      map_leaves(c, k, after_mode, before, k + 1, k);
      for (std::size_t w : sw.whens)
        for (const auto& r : b_.whens[w].reinits) after[r.state] = c.copy(r.value);
      if (tangents_) add_sensitivity_jump(k, *bd.switch_index, after);
    }
    out_.jump_output.push_back(m_.outputs.size());
    for (std::size_t i = 0; i < b_.states.size(); ++i)
      add_output(prefix + ".jump." + b_.states[i].info.name,
                 m_.arena.sub(after[i], m_.parameters[out_.phase_start[k] + i].symbol));
  }

  /// The held values the clauses fired at switch `sw` (the end of phase k)
  /// set: the value at s = 1 of phase k (states, algebraic variables and
  /// pre() from before the event; the clause's own targets new) minus the
  /// next phase's unknown. A control it reads is made continuous there.
  void add_held_values(std::size_t k, const PhaseSwitch& sw) {
    const PhaseMode& before = seq_.modes[lay_.mode[k]];
    const PhaseMode& after = seq_.modes[lay_.mode[k + 1]];
    std::vector<Expr> values;
    for (std::size_t w : sw.whens)
      for (const auto& a : b_.whens[w].assignments) {
        const auto j = held_index(a.target);
        if (!j) continue;
        const Expr v = phase_copy(k, after, before, {a.value}, nullptr, k + 1).front();
        const std::string name = "$boundary" + std::to_string(k + 1) + ".held." + b_.discrete[*j].info.name;
        out_.held_output.push_back(add_output(name, m_.arena.sub(v, held_[k + 1][*j])));
        values.push_back(a.value);
      }
    if (values.empty() || tangents_) return;  // with tangents every switch has ψ already
    std::vector<Expr> reads = symbolic::leaves(b_.arena, values);
    for (Expr e : leaves_through_steps(b_, values)) reads.push_back(e);
    for (std::size_t j = 0; j < b_.inputs.size(); ++j) {
      if (std::find(reads.begin(), reads.end(), b_.inputs[j].symbol) == reads.end()) continue;
      symbolic::VariableInfo info;
      info.name = "$boundary" + std::to_string(k + 1) + ".input." + b_.inputs[j].info.name;
      PhasedModel::Continuity c{j, add_parameter(info, 0.0), 0, 0};
      const Expr psi = m_.parameters[c.parameter].symbol;
      c.before_output = add_output(info.name + ".before", m_.arena.sub(m_.inputs[out_.input(k, j)].symbol, psi));
      c.after_output = add_output(info.name + ".after", m_.arena.sub(m_.inputs[out_.input(k + 1, j)].symbol, psi));
      out_.continuity.push_back(c);
    }
  }

  /// Per phase, sign·g for the indicators of the equations with a sign in its mode.
  void add_sign_outputs(std::size_t k) {
    const PhaseMode& mode = seq_.modes[lay_.mode[k]];
    for (std::size_t i = 0; i < b_.zero_crossings.size(); ++i) {
      if (!rel_.in_equations[i] || i >= mode.signs.size() || mode.signs[i] == 0) continue;
      const Expr g = phase_copy(k, mode, mode, {b_.zero_crossings[i]}).front();
      const std::string name = "$phase" + std::to_string(k + 1) + ".sign" + std::to_string(i + 1);
      out_.sign_output.push_back(add_output(name, mode.signs[i] > 0 ? g : m_.arena.neg(g)));
    }
  }

  /// Copies `roots` of the base arena as seen at the end of phase k (its
  /// states, inputs, algebraics), discrete values of `now` and pre() of `before`.
  std::vector<Expr> phase_copy(std::size_t k, const PhaseMode& now, const PhaseMode& before,
                               const std::vector<Expr>& roots, Copier* with = nullptr,
                               std::optional<std::size_t> held_now = {}, bool initial_pre = false) {
    Copier own(b_.arena, m_.arena);
    Copier& c = with ? *with : own;
    map_leaves(c, k, now, before, held_now);
    map_algebraics(c, k);
    if (initial_pre)  // at t0, before the event at initialisation: the start values
      for (std::size_t i = 0; i < b_.discrete.size(); ++i)
        if (unknown_[i]) c.set(b_.arena.pre(b_.discrete[i].symbol), m_.arena.constant(b_.discrete[i].start));
    c.copy_all(roots);
    std::vector<Expr> out;
    for (Expr r : roots) out.push_back(c.at(r));
    return out;
  }

  /// The event tangents of `roots` (tangent expressions of the base model)
  /// along the direction (δx, δp, δt) at the end of phase k: the tangent steps
  /// they need are copied with fresh algebraic symbols. δu = 0 (the controls
  /// are piecewise constant and continuous at a switch); δd of a held value
  /// is its sensitivity to `parameter` in phase k (0 without one); at t0
  /// (`initial`) pre() of a held value is its start value.
  std::vector<Expr> tangent_copy(std::size_t k, const PhaseMode& now, const PhaseMode& before,
                                 const std::vector<Expr>& dx, const std::vector<Expr>& dp, Expr dt,
                                 const std::vector<Expr>& roots, std::optional<std::size_t> parameter = {},
                                 bool initial = false) {
    const symbolic::EventTangents& t = *tangents_;
    Copier c(b_.arena, m_.arena);
    const Expr zero = m_.arena.constant(0.0);
    for (std::size_t i = 0; i < t.seed_x.size(); ++i) c.set(t.seed_x[i], dx[i]);
    for (std::size_t j = 0; j < t.seed_p.size(); ++j) c.set(t.seed_p[j], dp[j]);
    for (Expr u : t.seed_u) c.set(u, zero);
    for (std::size_t i = 0; i < t.seed_d.size(); ++i) {
      if (!t.seed_d[i].valid()) continue;
      const auto sd = parameter ? discrete_sensitivity(i, *parameter) : std::nullopt;
      c.set(t.seed_d[i], sd && !initial ? held_[k][*sd] : zero);
    }
    c.set(t.seed_t, dt);
    const std::vector<std::size_t> needed = needed_tangent_steps(roots);
    std::vector<Expr> all = roots;
    for (std::size_t s : needed) {
      const symbolic::Step& step = t.directional.steps[s];
      if (const auto* as = std::get_if<symbolic::Assignment>(&step)) {
        c.set(as->target, fresh_algebraic(as->target));
        all.push_back(as->value);
        continue;
      }
      const auto& b = std::get<symbolic::EquationBlock>(step);
      for (Expr u : b.unknowns) c.set(u, fresh_algebraic(u));
      all.insert(all.end(), b.residuals.begin(), b.residuals.end());
      all.insert(all.end(), b.offset.begin(), b.offset.end());
      for (const auto& e : b.jacobian) all.push_back(e.value);
    }
    std::vector<Expr> out = phase_copy(k, now, before, all, &c, {}, initial);
    for (std::size_t s : needed) copy_step(c, t.directional.steps[s]);
    out.resize(roots.size());
    return out;
  }

  /// Indices of the tangent steps `roots` depend on, in order.
  std::vector<std::size_t> needed_tangent_steps(const std::vector<Expr>& roots) {
    const auto& steps = tangents_->directional.steps;
    std::unordered_map<Expr, bool, symbolic::ExprHash> wanted;
    for (Expr l : symbolic::leaves(b_.arena, roots)) wanted[l] = true;
    std::vector<std::size_t> out;
    for (std::size_t s = steps.size(); s-- > 0;) {
      std::vector<Expr> targets, uses;
      if (const auto* as = std::get_if<symbolic::Assignment>(&steps[s])) {
        targets.push_back(as->target);
        uses.push_back(as->value);
      } else {
        const auto& b = std::get<symbolic::EquationBlock>(steps[s]);
        targets = b.unknowns;
        uses.insert(uses.end(), b.residuals.begin(), b.residuals.end());
        uses.insert(uses.end(), b.offset.begin(), b.offset.end());
        for (const auto& e : b.jacobian) uses.push_back(e.value);
      }
      if (std::none_of(targets.begin(), targets.end(), [&](Expr e) { return wanted.contains(e); })) continue;
      out.push_back(s);
      for (Expr l : symbolic::leaves(b_.arena, uses)) wanted[l] = true;
    }
    std::reverse(out.begin(), out.end());
    return out;
  }

  Expr fresh_algebraic(Expr base_symbol) {
    symbolic::VariableInfo info;
    info.name = "$tangent" + std::to_string(++tangent_symbols_) + "." + b_.arena.symbol_info(base_symbol).name;
    return add_algebraic(info);
  }

  /// The sensitivity states' jump at switch `sw` (the end of phase k), into
  /// `after` (docs/events.md): with η_j = dτ/dp_j = −δg(S⁻_j, e_j, 0) / δg(f⁻, 0, 1)
  /// at a crossing, δstart + k·δinterval along e_j at a tick,
  /// S⁺_j = δr(S⁻_j + f⁻ η_j, e_j, η_j) − f⁺ η_j, f⁺ the parameters φ that
  /// equal der(x) at the start of the next phase; the held values'
  /// sensitivities along the same directions.
  void add_sensitivity_jump(std::size_t k, std::size_t sw_index, std::vector<Expr>& after) {
    const PhaseSwitch& sw = seq_.switches[sw_index];
    const PhaseMode& before = seq_.modes[lay_.mode[k]];
    const PhaseMode& next = seq_.modes[lay_.mode[k + 1]];
    const std::size_t nb = b_.num_base_states(), nx = b_.states.size(), np = b_.parameters.size();
    auto& a = m_.arena;
    const Expr zero = a.constant(0.0), one = a.constant(1.0);
    std::vector<Expr> f_minus, f_plus;
    for (std::size_t i = 0; i < nb; ++i) {
      f_minus.push_back(find_algebraic(k, "der(" + b_.states[i].info.name + ")"));
      f_plus.push_back(m_.parameters[out_.fplus_parameter[sw_index] + i].symbol);
    }
    const std::string prefix = "$switch" + std::to_string(sw_index + 1) + ".fplus.";
    if (out_.fplus_output.size() == sw_index) {
      out_.fplus_output.push_back(m_.outputs.size());
      for (std::size_t i = 0; i < nb; ++i)
        add_output(prefix + b_.states[i].info.name,
                   a.sub(find_algebraic(k + 1, "der(" + b_.states[i].info.name + ")"), f_plus[i]));
    }
    if (out_.input_before_output.size() == sw_index) {
      out_.input_before_output.push_back(m_.outputs.size());
      for (std::size_t j = 0; j < b_.inputs.size(); ++j)
        add_output("$switch" + std::to_string(sw_index + 1) + ".input_before." + b_.inputs[j].info.name,
                   a.sub(m_.inputs[out_.input(k, j)].symbol, m_.parameters[out_.input_parameter[sw_index] + j].symbol));
      out_.input_after_output.push_back(m_.outputs.size());
      for (std::size_t j = 0; j < b_.inputs.size(); ++j)
        add_output("$switch" + std::to_string(sw_index + 1) + ".input_after." + b_.inputs[j].info.name,
                   a.sub(m_.inputs[out_.input(k + 1, j)].symbol, m_.parameters[out_.input_parameter[sw_index] + j].symbol));
    }
    // η = dτ/dp: a tick's from its start and interval, a crossing's from its indicator.
    const Expr tick_tangent = sw.timed ? base_tick_tangent(sw) : Expr();
    const Expr g_tangent = sw.timed ? Expr() : tangents_->indicators[sw.indicator];
    std::vector<Expr> dx(nx, zero), dp(np, zero);
    std::copy(f_minus.begin(), f_minus.end(), dx.begin());
    const Expr gdot = sw.timed ? one : tangent_copy(k, before, before, dx, dp, one, {g_tangent}).front();
    const auto by_parameter = sensitivity_states();  // j → (i, state)
    std::vector<Expr> reinit_roots;
    std::vector<std::size_t> reinit_state;
    for (std::size_t w : sw.whens)
      for (std::size_t r = 0; r < b_.whens[w].reinits.size(); ++r) {
        reinit_roots.push_back(tangents_->whens[w].reinits[r]);
        reinit_state.push_back(b_.whens[w].reinits[r].state);
      }
    std::map<std::size_t, std::tuple<std::vector<Expr>, std::vector<Expr>, Expr>> dirs;  // for held values
    for (const auto& [j, entries] : by_parameter) {
      std::fill(dx.begin(), dx.end(), zero);
      std::fill(dp.begin(), dp.end(), zero);
      for (const auto& [i, s] : entries) dx[i] = m_.states[out_.state(k, s)].symbol;
      dp[j] = one;
      const Expr eta = sw.timed ? tangent_copy(k, before, before, dx, dp, zero, {tick_tangent}, j).front()
                                : a.neg(a.div(tangent_copy(k, before, before, dx, dp, zero, {g_tangent}, j).front(), gdot));
      for (std::size_t i = 0; i < nb; ++i) dx[i] = a.add(dx[i], a.mul(f_minus[i], eta));
      dirs[j] = {dx, dp, eta};
      std::vector<Expr> dxplus(dx.begin(), dx.begin() + static_cast<std::ptrdiff_t>(nb));
      const std::vector<Expr> dr = tangent_copy(k, next, before, dx, dp, eta, reinit_roots, j);
      for (std::size_t r = 0; r < dr.size(); ++r) dxplus[reinit_state[r]] = dr[r];
      std::vector<bool> has(nb, false);
      for (const auto& [i, s] : entries) {
        after[s] = a.sub(dxplus[i], a.mul(f_plus[i], eta));
        has[i] = true;
      }
      const auto is_zero = [&](Expr e) { return a.kind(e) == ExprKind::Constant && a.constant_value(e) == 0.0; };
      for (std::size_t i = 0; i < nb; ++i)
        if (!has[i] && !is_zero(a.sub(dxplus[i], a.mul(f_plus[i], eta))))
          throw std::logic_error("multi-phase model: the sensitivity of " + b_.states[i].info.name + " to " +
                                 b_.parameters[j].info.name + " has no state but may jump at an event");
    }
    add_held_sensitivities(k, sw, dirs);
  }

  /// The base model's derivatives and algebraic variables as phase k's.
  void map_algebraics(Copier& c, std::size_t k) {
    for (std::size_t i = 0; i < b_.states.size(); ++i)
      c.set(b_.states[i].derivative, find_algebraic(k, "der(" + b_.states[i].info.name + ")"));
    for (const auto& a : b_.algebraics) c.set(a.symbol, find_algebraic(k, a.info.name));
  }

  /// δτ of a timed switch's tick in the base arena: δstart + k·δinterval
  /// (0 for a tick that is not start + k·interval over the parameters).
  Expr base_tick_tangent(const PhaseSwitch& sw) {
    if (!sw.tick) return b_.arena.constant(0.0);
    const std::size_t i = sw.tick->first;
    return b_.arena.add(tangents_->sample_starts[i],
                        b_.arena.mul(b_.arena.constant(sw.tick->second), tangents_->sample_intervals[i]));
  }

  Expr find_algebraic(std::size_t k, const std::string& name) {
    auto s = m_.arena.find_symbol(phase_name(k, name));
    if (!s) throw std::logic_error("multi-phase model: no algebraic " + phase_name(k, name));
    return *s;
  }

  OdeModel& b_;
  const RelationMap& rel_;
  const ModeSequence& seq_;
  const PhaseLayout& lay_;
  PhasedModel& out_;
  OdeModel& m_;
  std::size_t K_;
  std::vector<Expr> taus_;
  std::optional<symbolic::EventTangents> tangents_;  ///< with sensitivity states
  std::vector<std::vector<Expr>> held_;  ///< per phase and discrete variable: its held value (if unknown_)
  std::vector<bool> unknown_;            ///< per discrete variable: held, or the sensitivity of a held one
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> sensitivity_of_;  ///< (d, p) → ∂d/∂p's index
  std::size_t tangent_symbols_ = 0;
};

}  // namespace

PhaseLayout phase_layout(const ModeSequence& seq) {
  PhaseLayout out;
  out.mode.push_back(0);
  for (std::size_t k = 0; k < seq.switches.size(); ++k) {
    out.mode.push_back(k + 1);
    out.boundaries.push_back({seq.switches[k].time, k, seq.switches[k].states_after});
  }
  return out;
}

double fixed_end_time(const PhasedModel& pm, const PhaseBoundary& b) {
  if (!b.switch_index) return b.time;
  return pm.timed_switch[*b.switch_index] ? b.time : std::nan("");
}

PhasedModel build_phased_model(OdeModel& base, const RelationMap& rel, const ModeSequence& seq,
                               const PhaseLayout& layout, double t0, double tf, std::optional<std::size_t> lagrange) {
  PhasedModel out;
  PhaseBuilder(base, rel, seq, layout, out).build(t0, tf, lagrange);
  return out;
}

namespace {

class PhaseTimeSignal final : public runtime::InputSignal {
public:
  PhaseTimeSignal(std::shared_ptr<const runtime::InputSignal> s, double t0, double t1)
      : s_(std::move(s)), t0_(t0), t1_(t1) {}
  double value(double s) const override { return s_->value(t0_ + s * (t1_ - t0_)); }
  double value_before(double s) const override { return s_->value_before(t0_ + s * (t1_ - t0_)); }
  double derivative_before(double s) const override {
    return s_->derivative_before(t0_ + s * (t1_ - t0_)) * (t1_ - t0_);
  }
  std::vector<double> breakpoints(double a, double b) const override {
    std::vector<double> out;
    if (t1_ <= t0_) return out;
    for (double t : s_->breakpoints(t0_ + a * (t1_ - t0_), t0_ + b * (t1_ - t0_)))
      out.push_back((t - t0_) / (t1_ - t0_));
    return out;
  }

private:
  std::shared_ptr<const runtime::InputSignal> s_;
  double t0_, t1_;
};

}  // namespace

std::unique_ptr<runtime::InputSignal> phase_time_signal(std::shared_ptr<const runtime::InputSignal> signal,
                                                        double t0, double t1) {
  return std::make_unique<PhaseTimeSignal>(std::move(signal), t0, t1);
}

}  // namespace mo::tools
