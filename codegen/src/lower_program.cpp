// OdeModel → Program: sections in the order the printed methods run them.
#include <algorithm>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "derivatives.hpp"
#include "hessian_pattern.hpp"
#include "mo/codegen/program.hpp"
#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/ode_interpreter.hpp"
#include "mo/symbolic/event_tangents.hpp"
#include "mo/symbolic/mixed_order.hpp"
#include "mo/symbolic/substitute.hpp"
#include "mo/symbolic/traversal.hpp"
#include "section_builder.hpp"

namespace mo::codegen {

using symbolic::Expr;
using symbolic::ExprArena;
using symbolic::ExprKind;
using symbolic::OdeModel;
using symbolic::SymbolRole;

namespace {

/// A relation on a zero crossing: which indicator, and its value after a
/// downward crossing of that indicator.
struct RelationOnCrossing {
  Expr relation;
  int indicator;
  double value_if_down;
};

/// Relations under `roots` whose indicator is a zero crossing g = a - b (or
/// b - a) of `a op b`. Adds the differences to the arena.
std::vector<RelationOnCrossing> match_relations(OdeModel& m, const std::vector<Expr>& conditions) {
  std::vector<RelationOnCrossing> out;
  for (Expr e : symbolic::topological_order(m.arena, conditions)) {
    const ExprKind k = m.arena.kind(e);
    const bool less = k == ExprKind::Lt || k == ExprKind::Le;
    if (!less && k != ExprKind::Gt && k != ExprKind::Ge) continue;
    const Expr a = m.arena.operand(e, 0), b = m.arena.operand(e, 1);
    const Expr forward = m.arena.sub(a, b), backward = m.arena.sub(b, a);
    for (std::size_t i = 0; i < m.zero_crossings.size(); ++i) {
      // g = a - b crossing downwards makes a < b true; g = b - a makes a > b true.
      if (m.zero_crossings[i] == forward) {
        out.push_back({e, static_cast<int>(i), less ? 1.0 : 0.0});
        break;
      }
      if (m.zero_crossings[i] == backward) {
        out.push_back({e, static_cast<int>(i), less ? 0.0 : 1.0});
        break;
      }
    }
  }
  return out;
}

/// Every expression the event-tangent sections compute.
std::vector<Expr> event_roots(const OdeModel& m, const symbolic::EventTangents& t) {
  std::vector<Expr> roots;
  auto add_steps = [&](const std::vector<symbolic::Step>& steps) {
    for (const auto& s : steps) {
      if (const auto* as = std::get_if<symbolic::Assignment>(&s)) {
        roots.push_back(as->value);
        continue;
      }
      const auto& b = std::get<symbolic::EquationBlock>(s);
      roots.insert(roots.end(), b.residuals.begin(), b.residuals.end());
      roots.insert(roots.end(), b.offset.begin(), b.offset.end());
      for (const auto& e : b.jacobian) roots.push_back(e.value);
    }
  };
  add_steps(m.steps);
  add_steps(t.directional.steps);
  roots.insert(roots.end(), t.indicators.begin(), t.indicators.end());
  for (const auto& w : t.whens) {
    roots.insert(roots.end(), w.assignments.begin(), w.assignments.end());
    roots.insert(roots.end(), w.reinits.begin(), w.reinits.end());
  }
  return roots;
}

std::string names_of(const ExprArena& a, const std::vector<Expr>& symbols) {
  std::string out;
  for (std::size_t i = 0; i < symbols.size(); ++i) {
    if (i == 4) return out + ", ... (" + std::to_string(symbols.size()) + " unknowns)";
    out += (i ? ", " : "") + a.symbol_info(symbols[i]).name;
  }
  return out;
}

void check_targets(const OdeModel& m) {
  for (const auto& s : m.steps) {
    std::vector<Expr> targets;
    if (const auto* as = std::get_if<symbolic::Assignment>(&s))
      targets = {as->target};
    else
      targets = std::get<symbolic::EquationBlock>(s).unknowns;
    for (Expr t : targets) {
      if (m.arena.kind(t) != ExprKind::Symbol)
        throw std::invalid_argument("code generation: a step target is not a variable symbol");
      const SymbolRole r = m.arena.symbol_info(t).role;
      if (r != SymbolRole::Algebraic && r != SymbolRole::Derivative)
        throw std::invalid_argument("code generation: step target " +
                                    m.arena.symbol_info(t).name +
                                    " is not an algebraic variable or a derivative");
    }
  }
}

class Lowering {
public:
  explicit Lowering(OdeModel& m) : m_(m) {}

  Program run() {
    check_targets(m_);
    for (const auto& d : m_.discrete) pre_discrete_.push_back(m_.arena.pre(d.symbol));
    {
      std::vector<Expr> conditions;
      for (const auto& w : m_.whens) conditions.push_back(w.condition);
      relations_ = match_relations(m_, conditions);
      // In the clauses' bodies too (the every-event mode equations of the
      // MSL friction: `startForward = … sa > tau0_max …`): at the root CVODES
      // reports, the indicator may be exactly 0, and the relation evaluated
      // from the values would still hold its old value (Modelica 3 §8.5: at
      // an event a relation takes its new value).
      std::vector<Expr> bodies;
      for (const auto& w : m_.whens) {
        for (const auto& as : w.assignments) bodies.push_back(as.value);
        for (const auto& r : w.reinits) bodies.push_back(r.value);
      }
      when_relations_ = match_relations(m_, bodies);
    }
    if (!m_.zero_crossings.empty() || !m_.whens.empty()) {
      tangents_ = symbolic::event_tangents(m_);
      event_relations_ = match_relations(m_, event_roots(m_, *tangents_));
    }
    derivatives_ = detail::build_derivatives(m_);
    second_ = detail::build_second_derivatives(m_, derivatives_);
    // The arena is complete from here on.
    slots_.emplace(m_.arena.size());
    layout();
    delay_lines();
    steps();
    outputs();
    starts();
    samples();
    delay_sections();
    events();
    if (tangents_) event_tangents();
    jacobians();
    p_.num_slots = slots_->count();
    p_.node_slots = slots_->all();
    return std::move(p_);
  }

private:
  const ExprArena& arena() const { return m_.arena; }

  Section& new_section(const std::string& name, int& index) {
    index = static_cast<int>(p_.sections.size());
    p_.sections.push_back(Section{name, {}, false});
    return p_.sections.back();
  }
  detail::SectionBuilder builder(const detail::Validity& valid) {
    return detail::SectionBuilder(m_.arena, *slots_, p_, valid);
  }

  void layout() {
    auto place = [&](auto const& vars) {
      Slot first = slots_->count();
      for (const auto& v : vars) slots_->of(v.symbol);
      return first;
    };
    p_.layout.states = place(m_.states);
    p_.layout.inputs = place(m_.inputs);
    p_.layout.parameters = place(m_.parameters);
    p_.layout.time = m_.time.valid() ? slots_->of(m_.time) : slots_->fresh();
    p_.layout.discrete = place(m_.discrete);
    p_.layout.pre_discrete = slots_->count();
    for (Expr e : pre_discrete_) slots_->of(e);
    const auto& s = derivatives_.seeds;
    p_.layout.seeds_x = slots_->count();
    for (Expr e : s) slots_->of(e);
    p_.layout.seeds_u = p_.layout.seeds_x + static_cast<Slot>(m_.states.size());
    p_.layout.seeds_p = p_.layout.seeds_u + static_cast<Slot>(m_.inputs.size());
    p_.layout.seeds2 = slots_->count();
    for (Expr e : second_.seeds) slots_->of(e);
  }

  /// Emits model steps (assignments and blocks) into `section`; `what`
  /// prefixes the blocks' descriptions.
  void emit_steps(const std::vector<symbolic::Step>& steps, int section, detail::SectionBuilder& b,
                  const std::string& what) {
    std::size_t number = 0;
    for (const auto& step : steps) {
      Section& s = p_.sections[static_cast<std::size_t>(section)];
      if (const auto* as = std::get_if<symbolic::Assignment>(&step)) {
        b.assign(slots_->of(as->target), as->value, s);
        continue;
      }
      const auto& blk = std::get<symbolic::EquationBlock>(step);
      std::string description = what + (blk.linear ? "linear" : "nonlinear") + " block " +
                                std::to_string(++number) + " for " + names_of(arena(), blk.unknowns);
      const char* separator = "\n  equations: ";  // then where its equations are written
      for (const std::string& origin : blk.origins)
        if (!origin.empty()) description += std::exchange(separator, "\n    ") + origin;
      b.block(blk, description, p_.sections[static_cast<std::size_t>(section)]);
      if (!blk.linear) bounds(blk, p_.blocks.back());
    }
  }

  void steps() {
    new_section("steps", p_.steps);
    auto b = builder({});
    emit_steps(m_.steps, p_.steps, b, "");
    Section& s = p_.sections[static_cast<std::size_t>(p_.steps)];
    for (const auto& x : m_.states) p_.derivative_slots.push_back(b.root(x.derivative, s));
    after_steps_ = b.valid();
  }

  /// The unknowns' nominal, min and max (algebraic variables declare them;
  /// derivatives have none), for the Newton solve.
  void bounds(const symbolic::EquationBlock& blk, BlockCode& code) {
    if (algebraic_info_.empty())
      for (const auto& v : m_.algebraics) algebraic_info_.emplace(v.symbol.id(), &v.info);
    if (algebraic_info_.size() < m_.algebraics.size() + m_.initial_unknowns.size())
      for (const auto& v : m_.initial_unknowns) algebraic_info_.emplace(v.symbol.id(), &v.info);
    for (Expr z : blk.unknowns) {
      symbolic::VariableInfo info;
      if (auto it = algebraic_info_.find(z.id()); it != algebraic_info_.end()) info = *it->second;
      code.nominal.push_back(info.nominal);
      code.lower.push_back(info.min);
      code.upper.push_back(info.max);
    }
  }

  void outputs() {
    new_section("outputs", p_.outputs);
    auto b = builder(after_steps_);
    for (const auto& y : m_.outputs)
      p_.output_slots.push_back(b.root(y.value, p_.sections[static_cast<std::size_t>(p_.outputs)]));
  }

  void starts() {
    new_section("starts", p_.starts);
    auto b = builder({});
    emit_steps(m_.initial_steps, p_.starts, b, "initial system: ");
    for (const auto& x : m_.states)
      p_.start_slots.push_back(b.root(x.start, p_.sections[static_cast<std::size_t>(p_.starts)]));
    after_starts_ = b.valid();
    // Start values at the default parameters, for info() (NaN where the
    // initial system has no solution there: the run time reports it).
    std::vector<double> p;
    for (const auto& par : m_.parameters) p.push_back(par.value);
    try {
      p_.start_values = symbolic::OdeInterpreter(m_).initial_state(p);
    } catch (const symbolic::BlockFailure&) {
      p_.start_values.assign(m_.states.size(), std::numeric_limits<double>::quiet_NaN());
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("code generation: a start value depends on "
                                              "something other than parameters: ") + e.what());
    }
  }

  /// The start and interval of every sample() (over parameters, the start
  /// also over computed parameters: their states, loaded from x0).
  void samples() {
    if (m_.samples.empty()) return;
    new_section("samples", p_.samples_section);
    auto b = builder({});
    Section& s = p_.sections[static_cast<std::size_t>(p_.samples_section)];
    for (const auto& smp : m_.samples) {
      SampleCode code;
      code.flag = smp.flag;
      code.start = b.root(smp.start, s);
      code.interval = b.root(smp.interval, s);
      p_.samples.push_back(code);
    }
  }

  /// The Delay leaves of everything the sections compute (and of the
  /// delayed expressions themselves: delay(delay(x, 1), 1)), by node id.
  std::vector<Expr> delay_leaves() const {
    std::vector<Expr> roots = m_.equation_expressions();
    const std::vector<Expr> events = m_.event_expressions();
    roots.insert(roots.end(), events.begin(), events.end());
    return symbolic::delay_leaves(arena(), roots);
  }

  /// A DelayCode per delay() (before the steps, which compute the varying
  /// ones): varying if T reads anything but parameters.
  void delay_lines() {
    delays_ = delay_leaves();
    // The step targets that depend on sensitivity states (one pass: steps
    // are in evaluation order).
    std::unordered_set<Expr, symbolic::ExprHash> of_sensitivities;
    for (const auto& x : m_.states)
      if (x.sensitivity) of_sensitivities.insert(x.symbol);
    auto reads = [&](std::span<const Expr> roots) {
      for (Expr leaf : symbolic::leaves(arena(), roots))
        if (of_sensitivities.count(leaf)) return true;
      return false;
    };
    if (!of_sensitivities.empty())
      for (const auto& step : m_.steps) {
        if (const auto* as = std::get_if<symbolic::Assignment>(&step)) {
          if (reads(std::span(&as->value, 1))) of_sensitivities.insert(as->target);
        } else if (const auto& blk = std::get<symbolic::EquationBlock>(step); reads(blk.residuals)) {
          of_sensitivities.insert(blk.unknowns.begin(), blk.unknowns.end());
        }
      }
    for (Expr d : delays_) {
      DelayCode code;
      code.value = slots_->of(d);
      const Expr t = arena().operand(d, 1);
      for (Expr leaf : symbolic::leaves(arena(), std::span(&t, 1)))
        code.varying = code.varying || arena().kind(leaf) != ExprKind::Symbol ||
                       arena().symbol_info(leaf).role != SymbolRole::Parameter;
      const Expr e = arena().operand(d, 0);
      code.of_sensitivities = reads(std::span(&e, 1));
      p_.delay_lines.emplace(d.id(), static_cast<int>(p_.delays.size()));
      p_.delays.push_back(code);
    }
  }

  /// T and Tmax over the parameters (and x0, as sample() times; a varying T
  /// is the steps' slot), the delayed expressions after the steps.
  void delay_sections() {
    if (delays_.empty()) return;
    new_section("delay_times", p_.delay_times);
    auto bt = builder({});
    for (std::size_t k = 0; k < delays_.size(); ++k) {
      Section& s = p_.sections[static_cast<std::size_t>(p_.delay_times)];
      DelayCode& code = p_.delays[k];
      const Expr t = arena().operand(delays_[k], 1);
      code.time = code.varying ? slots_->of(t) : bt.root(t, s);
      code.max = bt.root(arena().operand(delays_[k], 2), s);
    }
    new_section("delay_arguments", p_.delay_arguments);
    auto ba = builder(after_steps_);
    for (std::size_t k = 0; k < delays_.size(); ++k)
      p_.delays[k].argument = ba.root(arena().operand(delays_[k], 0), p_.sections[static_cast<std::size_t>(p_.delay_arguments)]);
  }

  void events() {
    new_section("crossings", p_.crossings);
    {
      auto b = builder(after_steps_);
      for (Expr g : m_.zero_crossings)
        p_.crossing_slots.push_back(b.root(g, p_.sections[static_cast<std::size_t>(p_.crossings)]));
    }
    // pre(v) of a continuous variable is v's value when the handler starts;
    // pre(discrete) slots are loaded by the printed methods.
    for (std::uint32_t id = 0; id < arena().size(); ++id) {
      const Expr e(id);
      if (arena().kind(e) != ExprKind::Pre) continue;
      const Expr v = arena().operand(e, 0);
      if (arena().symbol_info(v).role != SymbolRole::Discrete)
        p_.pre_copies.emplace_back(slots_->of(e), slots_->of(v));
    }
    new_section("conditions", p_.conditions);
    {
      auto b = builder(after_steps_);
      for (const auto& r : relations_) b.override_relation(r.relation, r.indicator, r.value_if_down);
      for (const auto& w : m_.whens)
        p_.condition_slots.push_back(
            b.root(w.condition, p_.sections[static_cast<std::size_t>(p_.conditions)]));
    }
    const std::vector<bool> before_steps = symbolic::every_event_before_steps(m_);
    for (std::size_t k = 0; k < m_.whens.size(); ++k) {
      const auto& w = m_.whens[k];
      WhenCode code;
      code.every_event = w.every_event;
      code.terminates = w.terminates;
      code.terminate_message = w.terminate_message;
      code.group = w.prioritised ? w.group : -1;  // -1: fires on its own
      code.branch = w.branch;
      code.before_steps = before_steps[k];
      new_section("when" + std::to_string(k), code.section);
      auto b = builder(after_steps_);
      for (const auto& r : when_relations_) b.override_relation(r.relation, r.indicator, r.value_if_down);
      Section& s = p_.sections[static_cast<std::size_t>(code.section)];
      for (const auto& as : w.assignments) {
        if (arena().kind(as.target) != ExprKind::Symbol ||
            arena().symbol_info(as.target).role != SymbolRole::Discrete)
          throw std::invalid_argument("code generation: a when-clause assigns a non-discrete variable");
        code.assignments.emplace_back(slots_->of(as.target), b.root(as.value, s));
      }
      for (const auto& r : w.reinits) {
        if (r.state >= m_.states.size())
          throw std::invalid_argument("code generation: reinit of a state index out of range");
        code.reinits.emplace_back(r.state, b.root(r.value, s));
      }
      p_.whens.push_back(std::move(code));
    }
  }

  /// A builder for the event-tangent chain: relations on indicators follow cross[].
  detail::SectionBuilder event_builder(const detail::Validity& valid) {
    auto b = builder(valid);
    for (const auto& r : event_relations_) b.override_relation(r.relation, r.indicator, r.value_if_down);
    return b;
  }

  void emit_steps(detail::SectionBuilder& b, int section, const std::vector<symbolic::Step>& steps,
                  const std::string& what) {
    std::size_t number = 0;
    for (const auto& step : steps) {
      Section& s = p_.sections[static_cast<std::size_t>(section)];
      if (const auto* as = std::get_if<symbolic::Assignment>(&step)) {
        b.assign(slots_->of(as->target), as->value, s);
        continue;
      }
      const auto& blk = std::get<symbolic::EquationBlock>(step);
      b.block(blk, what + " block " + std::to_string(++number), s);
      // Newton's scales and bounds, as in the model's own steps (without them
      // a torn block at an event read past empty arrays and did not move).
      if (!blk.linear) bounds(blk, p_.blocks.back());
    }
  }

  /// Sections of EventTangentCode: steps with relations from cross[], the
  /// tangent steps and indicator tangents, one section per when-clause.
  void event_tangents() {
    const symbolic::EventTangents& t = *tangents_;
    EventTangentCode& code = p_.event_tangents;
    for (Expr e : t.seed_x) code.seed_x.push_back(slots_->of(e));
    for (Expr e : t.seed_u) code.seed_u.push_back(slots_->of(e));
    for (Expr e : t.seed_p) code.seed_p.push_back(slots_->of(e));
    for (Expr e : t.seed_d) code.seed_d.push_back(e.valid() ? static_cast<int>(slots_->of(e)) : -1);
    code.seed_t = slots_->of(t.seed_t);
    new_section("event_rhs", code.rhs);
    auto b = event_builder({});
    emit_steps(m_.steps, code.rhs, b, "");  // the model's blocks, described as in the steps
    for (const auto& x : m_.states) b.root(x.derivative, p_.sections[static_cast<std::size_t>(code.rhs)]);
    new_section("event_tangent", code.tangent);
    auto bt = event_builder(b.valid());
    emit_steps(bt, code.tangent, t.directional.steps, "event tangent");
    for (Expr g : t.indicators)
      code.indicator_slots.push_back(bt.root(g, p_.sections[static_cast<std::size_t>(code.tangent)]));
    for (std::size_t i = 0; i < t.sample_starts.size(); ++i) {
      Section& s = p_.sections[static_cast<std::size_t>(code.tangent)];
      code.sample_start_slots.push_back(bt.root(t.sample_starts[i], s));
      code.sample_interval_slots.push_back(bt.root(t.sample_intervals[i], s));
    }
    for (const auto& w : t.whens) {
      int index = -1;
      new_section("when_tangent" + std::to_string(code.whens.size()), index);
      auto bw = event_builder(bt.valid());
      Section& s = p_.sections[static_cast<std::size_t>(index)];
      for (Expr e : w.assignments) code.assign_slots.push_back(bw.root(e, s));
      for (Expr e : w.reinits) code.reinit_slots.push_back(bw.root(e, s));
      code.whens.push_back(index);
    }
  }

  void jacobians() {
    const auto& d = derivatives_;
    const int nx = static_cast<int>(m_.states.size()), nu = static_cast<int>(m_.inputs.size()),
              np = static_cast<int>(m_.parameters.size());
    int jvp_steps = -1, jvp_outputs = -1, jvp_starts = -1;
    new_section("jvp_steps", jvp_steps);
    auto b = builder(after_steps_);
    std::size_t number = 0;
    for (const auto& step : d.directional.steps) {
      Section& s = p_.sections[static_cast<std::size_t>(jvp_steps)];
      if (const auto* as = std::get_if<symbolic::Assignment>(&step)) {
        b.assign(slots_->of(as->target), as->value, s);
        continue;
      }
      const auto& blk = std::get<symbolic::EquationBlock>(step);
      // Named by number only: the unknowns' names are generated, and the
      // text must not change between generations of the same model.
      b.block(blk, "Jacobian-vector product block " + std::to_string(++number), s);
    }
    auto row_slots = [&](auto& bld, int section, const std::vector<Expr>& rows) {
      std::vector<Slot> out;
      for (Expr r : rows)
        out.push_back(r.valid() ? bld.root(r, p_.sections[static_cast<std::size_t>(section)]) : 0);
      return out;
    };
    const std::vector<Slot> f_slots = row_slots(b, jvp_steps, d.f_rows);
    new_section("jvp_outputs", jvp_outputs);
    auto bo = builder(b.valid());
    const std::vector<Slot> h_slots = row_slots(bo, jvp_outputs, d.h_rows);
    new_section("jvp_starts", jvp_starts);
    auto bs = builder(after_starts_);
    emit_steps(d.initial_directional.steps, jvp_starts, bs, "Jacobian-vector product of the initial system: ");
    const std::vector<Slot> x0_slots = row_slots(bs, jvp_starts, d.x0_rows);

    const auto f_cols = detail::row_columns(arena(), d, d.f_rows);
    const auto h_cols = detail::row_columns(arena(), d, d.h_rows);
    const auto x0_cols = detail::seed_columns(arena(), d.seeds, {&d.initial_directional.steps}, d.x0_rows);
    struct Spec {
      const std::vector<std::vector<int>>* rows;
      const std::vector<Slot>* slots;
      int first, count;
      std::vector<int> base, product;
    };
    const Spec specs[7] = {
        {&f_cols, &f_slots, 0, nx, {p_.steps}, {jvp_steps}},
        {&f_cols, &f_slots, nx, nu, {p_.steps}, {jvp_steps}},
        {&f_cols, &f_slots, nx + nu, np, {p_.steps}, {jvp_steps}},
        {&h_cols, &h_slots, 0, nx, {p_.steps}, {jvp_steps, jvp_outputs}},
        {&h_cols, &h_slots, nx, nu, {p_.steps}, {jvp_steps, jvp_outputs}},
        {&h_cols, &h_slots, nx + nu, np, {p_.steps}, {jvp_steps, jvp_outputs}},
        {&x0_cols, &x0_slots, nx + nu, np, {p_.starts}, {jvp_starts}},
    };
    for (std::size_t k = 0; k < 7; ++k) {
      const Spec& sp = specs[k];
      JacobianCode& code = p_.jacobians[k];
      detail::pattern_and_colouring(*sp.rows, sp.first, sp.count, code);
      for (int c = 0; c < code.cols; ++c) {
        code.seed_slot.push_back(p_.layout.seeds_x + static_cast<Slot>(sp.first + c));
        for (int e = code.col_start[static_cast<std::size_t>(c)]; e < code.col_start[static_cast<std::size_t>(c) + 1]; ++e)
          code.entry_slot.push_back((*sp.slots)[static_cast<std::size_t>(code.row_index[static_cast<std::size_t>(e)])]);
      }
      code.base_sections = sp.base;
      code.product_sections = sp.product;
    }
    hessians(jvp_steps, jvp_outputs, b.valid(), bo.valid());
  }

  /// Sections of D²f and D²h, the Hessian patterns, colourings and products.
  void hessians(int jvp_steps, int jvp_outputs, const detail::Validity& after_jvp_steps,
                const detail::Validity& after_jvp_outputs) {
    const auto& d = derivatives_;
    const auto& s2 = second_;
    int hess_steps = -1, hess_outputs = -1;
    new_section("hessian_steps", hess_steps);
    auto b = builder(after_jvp_steps);
    std::size_t number = 0;
    for (const auto& step : s2.directional.steps) {
      Section& s = p_.sections[static_cast<std::size_t>(hess_steps)];
      if (const auto* as = std::get_if<symbolic::Assignment>(&step)) {
        b.assign(slots_->of(as->target), as->value, s);
        continue;
      }
      b.block(std::get<symbolic::EquationBlock>(step),
              "second-order derivative block " + std::to_string(++number), s);
    }
    auto row_slots = [&](auto& bld, int section, const std::vector<Expr>& rows) {
      std::vector<Slot> out;
      for (Expr r : rows)
        out.push_back(r.valid() ? bld.root(r, p_.sections[static_cast<std::size_t>(section)]) : 0);
      return out;
    };
    const std::vector<Slot> f_slots = row_slots(b, hess_steps, s2.f_rows);
    detail::Validity both = b.valid();
    for (std::size_t k = 0; k < both.size() && k < after_jvp_outputs.size(); ++k)
      both[k] = static_cast<std::uint8_t>(both[k] | after_jvp_outputs[k]);
    new_section("hessian_outputs", hess_outputs);
    auto bo = builder(both);
    const std::vector<Slot> h_slots = row_slots(bo, hess_outputs, s2.h_rows);
    // The structurally nonzero T_i(a, b) of each row, from the graph of the
    // second directional derivatives (hessian_pattern.hpp).
    const std::vector<const std::vector<symbolic::Step>*> steps{&d.directional.steps,
                                                                 &s2.directional.steps};
    auto pairs = [&](const std::vector<Expr>& rows) {
      return detail::second_order_pairs(arena(), d.seeds, s2.seeds, steps, rows);
    };
    hessian_code(pairs(s2.f_rows), f_slots, p_.hessians[0]);
    hessian_code(pairs(s2.h_rows), h_slots, p_.hessians[1]);
    p_.hessians[0].base_sections = {p_.steps};
    p_.hessians[0].sigma_sections = {jvp_steps};
    p_.hessians[0].product_sections = {hess_steps};
    p_.hessians[1].base_sections = {p_.steps};
    p_.hessians[1].sigma_sections = {jvp_steps, jvp_outputs};
    p_.hessians[1].product_sections = {hess_steps, hess_outputs};
  }

  /// Pattern (lower triangle), colouring and products from each row's pairs.
  /// Columns of a row that take part in one of its pairs get distinct
  /// colours, so that product (A, B) holds T_i(a, b) for the row's a of colour
  /// A and b of colour B alone; a product is kept if some row has that pair.
  void hessian_code(const std::vector<std::vector<std::pair<int, int>>>& pairs,
                    const std::vector<Slot>& slots, HessianCode& code) {
    const int n = static_cast<int>(d_size());
    code.n = n;
    std::vector<std::vector<int>> col_rows(static_cast<std::size_t>(n));  // lower triangle
    std::vector<std::vector<int>> rows(pairs.size());  // columns of each row's pairs
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      for (auto [r, c] : pairs[i]) {
        col_rows[static_cast<std::size_t>(c)].push_back(r);
        rows[i].push_back(r);
        rows[i].push_back(c);
      }
      std::sort(rows[i].begin(), rows[i].end());
      rows[i].erase(std::unique(rows[i].begin(), rows[i].end()), rows[i].end());
    }
    code.col_start.assign(1, 0);
    code.row_index.clear();
    for (auto& rs : col_rows) {
      std::sort(rs.begin(), rs.end());
      rs.erase(std::unique(rs.begin(), rs.end()), rs.end());
      code.row_index.insert(code.row_index.end(), rs.begin(), rs.end());
      code.col_start.push_back(static_cast<int>(code.row_index.size()));
    }
    auto find = [&](int r, int c) {
      const auto first = code.row_index.begin() + code.col_start[static_cast<std::size_t>(c)];
      const auto last = code.row_index.begin() + code.col_start[static_cast<std::size_t>(c) + 1];
      const auto it = std::lower_bound(first, last, r);
      if (it == last || *it != r) throw std::logic_error("internal error: Hessian entry outside its pattern");
      return static_cast<int>(it - code.row_index.begin());
    };
    JacobianCode colouring;
    detail::pattern_and_colouring(rows, 0, n, colouring);
    code.colours = colouring.colours;
    std::vector<int> colour(static_cast<std::size_t>(n), -1);
    for (std::size_t k = 0; k < code.colours.size(); ++k)
      for (int c : code.colours[k]) colour[static_cast<std::size_t>(c)] = static_cast<int>(k);
    const int nc = static_cast<int>(code.colours.size());
    std::vector<std::vector<HessianCode::Entry>> by_product(static_cast<std::size_t>(nc * nc));
    for (std::size_t i = 0; i < pairs.size(); ++i)
      for (auto [r, c] : pairs[i]) {
        const int A = std::min(colour[static_cast<std::size_t>(r)], colour[static_cast<std::size_t>(c)]);
        const int B = std::max(colour[static_cast<std::size_t>(r)], colour[static_cast<std::size_t>(c)]);
        by_product[static_cast<std::size_t>(A * nc + B)].push_back({static_cast<int>(i), slots[i], find(r, c)});
      }
    code.products.clear();
    for (int A = 0; A < nc; ++A)
      for (int B = A; B < nc; ++B)
        if (auto& entries = by_product[static_cast<std::size_t>(A * nc + B)]; !entries.empty())
          code.products.push_back({A, B, std::move(entries)});
  }

  std::size_t d_size() const {
    return m_.states.size() + m_.inputs.size() + m_.parameters.size();
  }

  OdeModel& m_;
  Program p_;
  std::optional<detail::SlotMap> slots_;
  std::vector<Expr> pre_discrete_;
  std::vector<Expr> delays_;  // the Delay nodes, in DelayCode order
  std::vector<RelationOnCrossing> relations_;       // relations of the when-conditions
  std::vector<RelationOnCrossing> when_relations_;  // relations of the when-clauses' bodies
  std::optional<symbolic::EventTangents> tangents_;
  std::vector<RelationOnCrossing> event_relations_;  // relations of the event_tangents sections
  detail::Derivatives derivatives_;
  detail::SecondDerivatives second_;
  detail::Validity after_steps_, after_starts_;
  std::unordered_map<std::size_t, const symbolic::VariableInfo*> algebraic_info_;  ///< symbol id → declaration
};

}  // namespace

Program lower_to_program(OdeModel& model) { return Lowering(model).run(); }

}  // namespace mo::codegen
