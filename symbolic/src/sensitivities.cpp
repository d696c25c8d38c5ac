// Forward sensitivity equations; see sensitivities.hpp.
#include "mo/symbolic/sensitivities.hpp"

#include <stdexcept>
#include <unordered_set>

#include "mo/symbolic/differentiate.hpp"
#include "mo/symbolic/directional.hpp"
#include "mo/symbolic/event_tangents.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/substitute.hpp"
#include "mo/symbolic/traversal.hpp"

namespace mo::symbolic {

namespace {


/// Targets and used leaves of one step, for dependency propagation.
struct StepLeaves {
  std::vector<Expr> targets;
  std::vector<Expr> used;
};

/// The leaves of `roots` and, for dependencies, those of their delayed
/// expressions: delay(e) varies with a parameter that e's past varies with.
std::vector<Expr> leaves_through_delays(const ExprArena& a, std::span<const Expr> roots) {
  std::vector<Expr> out = leaves(a, roots);
  for (Expr d : delay_leaves(a, roots)) {
    const Expr e = a.operand(d, 0);
    const std::vector<Expr> more = leaves(a, std::span(&e, 1));
    out.insert(out.end(), more.begin(), more.end());
  }
  return out;
}

std::vector<StepLeaves> step_leaves(const OdeModel& m) {
  std::vector<StepLeaves> out;
  out.reserve(m.steps.size());
  for (const Step& s : m.steps) {
    StepLeaves sl;
    if (const auto* a = std::get_if<Assignment>(&s)) {
      sl.targets = {a->target};
      sl.used = leaves_through_delays(m.arena, std::span(&a->value, 1));
    } else {
      const auto& b = std::get<EquationBlock>(s);
      sl.targets = b.unknowns;
      sl.used = leaves_through_delays(m.arena, b.residuals);
    }
    out.push_back(std::move(sl));
  }
  return out;
}

/// Which steps read each leaf, and which state a derivative symbol belongs to.
struct Users {
  std::unordered_map<Expr, std::vector<std::size_t>, ExprHash> steps_using;
  std::unordered_map<Expr, std::size_t, ExprHash> state_of_derivative;
};

Users users(const OdeModel& m, const std::vector<StepLeaves>& steps, std::size_t nx) {
  Users u;
  for (std::size_t s = 0; s < steps.size(); ++s)
    for (Expr l : steps[s].used) u.steps_using[l].push_back(s);
  for (std::size_t i = 0; i < nx; ++i) u.state_of_derivative[m.states[i].derivative] = i;
  return u;
}

/// True if an event expression (indicator, when-condition, reinit value,
/// discrete assignment, sample() start or interval) reads one of `reached` (leaves that depend on p).
bool touches_events(const OdeModel& m, const std::unordered_set<Expr, ExprHash>& reached) {
  std::vector<Expr> roots = m.event_expressions();
  for (const OdeSample& smp : m.samples) {  // the times of sample()'s events
    roots.push_back(smp.start);
    roots.push_back(smp.interval);
  }
  for (Expr l : leaves_through_delays(m.arena, roots)) {
    // pre(v) of a continuous v is v's value at the event.
    const Expr v = m.arena.kind(l) == ExprKind::Pre ? m.arena.operand(l, 0) : l;
    if (reached.count(l) || reached.count(v)) return true;
  }
  return false;
}

/// The event map's derivatives (event_tangents.hpp) take a delay() as a
/// constant: refused where the delayed value depends on the parameter.
void check_event_delays(const OdeModel& m, const std::unordered_set<Expr, ExprHash>& reached) {
  const std::vector<Expr> roots = m.event_expressions();
  for (Expr d : delay_leaves(m.arena, roots)) {
    const Expr e = m.arena.operand(d, 0);
    for (Expr l : leaves_through_delays(m.arena, std::span(&e, 1)))
      if (reached.count(l))
        throw std::invalid_argument("sensitivities: " + to_modelica(m.arena, d) +
                                    " in an event condition, a when-clause or a reinit depends on the "
                                    "parameter; sensitivities through it are not supported");
  }
}

/// The base states whose value depends on parameter symbol `p`: a worklist
/// over leaves (parameter → steps reading it → their targets → states whose
/// derivative they are → steps reading those states ...), linear in the model.
/// `through_events`: set if p reaches an event expression.
std::vector<bool> influenced_states(const OdeModel& m, const std::vector<StepLeaves>& steps,
                                    const Users& u, Expr p, std::size_t nx,
                                    const std::vector<Expr>& start_derivative, bool& through_events) {
  std::vector<bool> hit(nx, false), step_done(steps.size(), false);
  std::vector<Expr> work{p};
  for (std::size_t i = 0; i < nx; ++i)
    if (!m.arena.is_constant(start_derivative[i], 0.0)) {
      hit[i] = true;
      work.push_back(m.states[i].symbol);
    }
  std::unordered_set<Expr, ExprHash> reached{p};
  while (!work.empty()) {
    const Expr leaf = work.back();
    work.pop_back();
    reached.insert(leaf);
    const auto it = u.steps_using.find(leaf);
    if (it == u.steps_using.end()) continue;
    for (std::size_t s : it->second) {
      if (step_done[s]) continue;
      step_done[s] = true;
      for (Expr t : steps[s].targets) {
        work.push_back(t);
        const auto st = u.state_of_derivative.find(t);
        if (st != u.state_of_derivative.end() && !hit[st->second]) {
          hit[st->second] = true;
          work.push_back(m.states[st->second].symbol);
        }
      }
    }
  }
  // At an event the sensitivities jump (S+ = r_x S- + r_p + (r_x f- + r_t - f+) dtau/dp):
  // a parameter that reaches an indicator, a when-condition, a reinit or a
  // discrete assignment moves the event or its effect, and through the jump
  // any state. All base states then get sensitivities (a superset).
  through_events = touches_events(m, reached);
  if (through_events) {
    check_event_delays(m, reached);
    std::fill(hit.begin(), hit.end(), true);
  }
  return hit;
}

/// What the sensitivities of all parameters add; appended to the model at the
/// end so that each parameter differentiates the base steps only.
struct Additions {
  std::vector<Step> steps;
  std::vector<OdeAlgebraic> algebraics;
  std::vector<OdeOutput> outputs;
  std::vector<Step> initial_steps;  ///< ∂/∂p of the initial system's blocks
  std::vector<OdeAlgebraic> initial_unknowns;
};

/// delay(e, T, Tmax) along a parameter is delay(∂e, T, Tmax), T not
/// depending on it. ∂e is known only after the steps are differentiated, so
/// they are differentiated with a placeholder symbol per delay, replaced by
/// DelayedDerivatives::replacements afterwards.
struct DelayedDerivatives {
  std::vector<Expr> delays, placeholders;  ///< ascending delay ids

  DelayedDerivatives(OdeModel& m, const OdeParameter& par, ExprMap& seeds) {
    const std::vector<Expr> roots = m.equation_expressions();
    ExprArena& a = m.arena;
    for (Expr d : delay_leaves(a, roots)) {
      const Expr times[] = {a.operand(d, 1), a.operand(d, 2)};
      for (Expr l : leaves(a, times)) {
        if (l == par.symbol)
          throw std::invalid_argument("sensitivities: the delay time of " + to_modelica(a, d) +
                                      " depends on parameter " + par.info.name +
                                      "; sensitivities to a delay time are not supported");
        if (a.kind(l) != ExprKind::Symbol || a.symbol_info(l).role != SymbolRole::Parameter)
          throw std::invalid_argument("sensitivities: the delay time of " + to_modelica(a, d) +
                                      " varies; sensitivities through a varying delay time are not supported");
      }
      const Expr p = a.symbol(sensitivity_name("$delay" + std::to_string(d.id()), par.info.name),
                              SymbolRole::Algebraic, -1);
      delays.push_back(d);
      placeholders.push_back(p);
      seeds[d] = p;
    }
  }

  /// The placeholders → delay(∂e, T, Tmax), ∂e along `d`; inner delays first.
  ExprMap replacements(OdeModel& m, const Directional& d) const {
    ExprMap out;
    ExprArena& a = m.arena;
    for (std::size_t k = 0; k < delays.size(); ++k) {
      const Expr de = substitute(a, derivative_along(m, d, a.operand(delays[k], 0)), out);
      out[placeholders[k]] = a.delay(de, a.operand(delays[k], 1), a.operand(delays[k], 2));
    }
    return out;
  }
};

void replace_in_steps(ExprArena& a, std::vector<Step>& steps, const ExprMap& map) {
  if (map.empty()) return;
  std::vector<Expr*> targets;
  for (Step& s : steps) {
    if (auto* as = std::get_if<Assignment>(&s)) {
      targets.push_back(&as->value);
      continue;
    }
    auto& b = std::get<EquationBlock>(s);
    for (Expr& e : b.residuals) targets.push_back(&e);
    for (BlockEntry& e : b.jacobian) targets.push_back(&e.value);
    for (Expr& e : b.offset) targets.push_back(&e);
  }
  substitute_in_place(a, targets, map);
}

/// The discrete sensitivities ∂d/∂p of the discrete variables with `moving`
/// (discrete_with_tangents): new discrete variables, 0 at t0 and set by the
/// run time at events, seeded for d and pre(d) in `seeds`.
void add_discrete_sensitivities(OdeModel& m, const std::vector<bool>& moving, std::size_t k,
                                ExprMap& seeds) {
  ExprArena& a = m.arena;
  const OdeParameter& par = m.parameters[k];
  std::unordered_map<Expr, Expr, ExprHash> companion;
  for (std::size_t i = 0; i < moving.size(); ++i) {
    if (!moving[i]) continue;
    OdeDiscrete c;
    c.info.name = sensitivity_name(m.discrete[i].info.name, par.info.name);
    c.info.description = "sensitivity of " + m.discrete[i].info.name + " to " + par.info.name;
    c.symbol = a.symbol(c.info.name, SymbolRole::Discrete, static_cast<std::int32_t>(m.discrete.size()));
    c.sensitivity = DiscreteSensitivityOf{i, k};
    seeds[m.discrete[i].symbol] = c.symbol;
    companion[m.discrete[i].symbol] = c.symbol;
    m.discrete.push_back(std::move(c));
  }
  if (companion.empty()) return;
  // Between events pre(d) = d.
  for (Expr l : leaves(a, m.equation_expressions()))
    if (a.kind(l) == ExprKind::Pre)
      if (const auto it = companion.find(a.operand(l, 0)); it != companion.end()) seeds[l] = it->second;
}

void add_for_parameter(OdeModel& m, const std::vector<StepLeaves>& steps, const Users& u,
                       std::size_t k, std::size_t nx, std::size_t ny,
                       const std::vector<bool>& moving, Additions& add) {
  const OdeParameter par = m.parameters[k];
  ExprArena& a = m.arena;
  // ∂x0/∂p through the initial system (implicit function theorem on its blocks).
  const Directional init = differentiate_steps(
      m, m.initial_steps, ExprMap{{par.symbol, a.constant(1.0)}},
      [&](const std::string& v) { return sensitivity_name(v, par.info.name); });
  std::vector<Expr> start_derivative;
  for (std::size_t i = 0; i < nx; ++i)
    start_derivative.push_back(derivative_along(m, init, m.states[i].start));
  add.initial_steps.insert(add.initial_steps.end(), init.steps.begin(), init.steps.end());
  add.initial_unknowns.insert(add.initial_unknowns.end(), init.symbols.begin(), init.symbols.end());
  bool through_events = false;
  const std::vector<bool> hit =
      influenced_states(m, steps, u, par.symbol, nx, start_derivative, through_events);
  ExprMap seeds{{par.symbol, a.constant(1.0)}};
  // Unless p reaches an event expression, no discrete value depends on it.
  if (through_events) add_discrete_sensitivities(m, moving, k, seeds);
  std::vector<std::size_t> new_states;
  for (std::size_t i = 0; i < nx; ++i) {
    if (!hit[i]) continue;
    const OdeState& x = m.states[i];
    OdeState s;
    s.info.name = sensitivity_name(x.info.name, par.info.name);
    s.info.description = "sensitivity of " + x.info.name + " to " + par.info.name;
    s.info.nominal = x.info.nominal;
    const auto index = static_cast<std::int32_t>(m.states.size());
    s.symbol = a.symbol(s.info.name, SymbolRole::State, index);
    s.derivative = a.symbol("der(" + s.info.name + ")", SymbolRole::Derivative, index);
    s.start = start_derivative[i];
    s.fixed = x.fixed;
    s.sensitivity = SensitivityOf{i, k};
    seeds[x.symbol] = s.symbol;
    new_states.push_back(m.states.size());
    m.states.push_back(std::move(s));
  }
  const DelayedDerivatives delayed(m, par, seeds);
  Directional d = differentiate_steps(
      m, seeds, [&](const std::string& v) { return sensitivity_name(v, par.info.name); });
  const ExprMap delay_map = delayed.replacements(m, d);
  auto replaced = [&](Expr e) { return delay_map.empty() ? e : substitute(a, e, delay_map); };
  replace_in_steps(a, d.steps, delay_map);
  add.steps.insert(add.steps.end(), d.steps.begin(), d.steps.end());
  add.algebraics.insert(add.algebraics.end(), d.symbols.begin(), d.symbols.end());
  for (std::size_t si : new_states) {
    const OdeState& s = m.states[si];
    const auto it = d.derivative.find(m.states[s.sensitivity->state].derivative);
    add.steps.emplace_back(
        Assignment{s.derivative, it == d.derivative.end() ? a.constant(0.0) : replaced(it->second)});
  }
  for (std::size_t j = 0; j < ny; ++j) {
    OdeOutput y;
    y.info.name = sensitivity_name(m.outputs[j].info.name, par.info.name);
    y.info.description = "sensitivity of output " + m.outputs[j].info.name;
    y.value = replaced(derivative_along(m, d, m.outputs[j].value));
    add.outputs.push_back(std::move(y));
  }
}

}  // namespace

std::string sensitivity_name(const std::string& variable, const std::string& parameter) {
  return "d(" + variable + ")/d(" + parameter + ")";
}

void add_sensitivities(OdeModel& model, std::span<const std::size_t> parameters) {
  if (model.num_base_states() != model.states.size())
    throw std::invalid_argument("add_sensitivities: the model already has sensitivity states");
  std::unordered_set<std::size_t> seen;
  for (std::size_t k : parameters) {
    if (k >= model.parameters.size())
      throw std::invalid_argument("add_sensitivities: parameter index out of range");
    if (!seen.insert(k).second)
      throw std::invalid_argument("add_sensitivities: parameter listed twice: " +
                                  model.parameters[k].info.name);
  }
  const std::size_t nx = model.states.size(), ny = model.outputs.size();
  const std::vector<StepLeaves> steps = step_leaves(model);
  const Users u = users(model, steps, nx);
  const std::vector<bool> moving = discrete_with_tangents(model);
  Additions add;
  for (std::size_t k : parameters) add_for_parameter(model, steps, u, k, nx, ny, moving, add);
  auto append = [](auto& to, auto& from) { to.insert(to.end(), from.begin(), from.end()); };
  append(model.steps, add.steps);
  append(model.algebraics, add.algebraics);
  append(model.outputs, add.outputs);
  append(model.initial_steps, add.initial_steps);
  append(model.initial_unknowns, add.initial_unknowns);
}

}  // namespace mo::symbolic
