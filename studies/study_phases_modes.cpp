// The mode sequence of a simulation; see study_phases.hpp.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "mo/runtime/simulate.hpp"
#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/traversal.hpp"
#include "study_phases.hpp"

namespace mo::tools {

namespace {

/// A model that forwards to another and records every call of its event handler.
class EventRecorder final : public runtime::Model {
public:
  struct Call {
    double t = 0.0;
    std::vector<int> crossings;
    bool time_event = false;
    std::vector<double> x_before, x_after, d_before, d_after;
    std::vector<int> fired;  ///< per when-clause: times it fired in this call
  };

  explicit EventRecorder(std::unique_ptr<runtime::Model> inner) : inner_(std::move(inner)) {}

  std::vector<Call> calls;
  std::vector<int> initial_fired;  ///< per when-clause: times it fired in the last initial_state()

  const runtime::ModelInfo& info() const override { return inner_->info(); }
  std::unique_ptr<Model> clone() const override { return std::make_unique<EventRecorder>(inner_->clone()); }
  using Model::initial_state;
  void initial_state(double t0, std::span<const double> u0, std::span<const double> p,
                     std::span<double> x0) override {
    inner_->initial_state(t0, u0, p, x0);
    initial_fired = inner_->take_fired_counts();
  }
  void rhs(double t, std::span<const double> x, std::span<const double> u, std::span<const double> p,
           std::span<double> xdot) override {
    inner_->rhs(t, x, u, p, xdot);
  }
  void outputs(double t, std::span<const double> x, std::span<const double> u, std::span<const double> p,
               std::span<double> y) override {
    inner_->outputs(t, x, u, p, y);
  }
  const runtime::Sparsity& jacobian_sparsity(runtime::Jacobian block) const override {
    return inner_->jacobian_sparsity(block);
  }
  void jacobian_values(runtime::Jacobian block, double t, std::span<const double> x, std::span<const double> u,
                       std::span<const double> p, std::span<double> values) override {
    inner_->jacobian_values(block, t, x, u, p, values);
  }
  void event_indicators(double t, std::span<const double> x, std::span<const double> u,
                        std::span<const double> p, std::span<double> g) override {
    inner_->event_indicators(t, x, u, p, g);
  }
  double next_time_event(double t) const override { return inner_->next_time_event(t); }
  runtime::EventResponse handle_event(const runtime::EventCause& cause, std::span<double> x,
                                      std::span<const double> u, std::span<const double> p) override {
    Call c;
    c.t = cause.t;
    c.crossings.assign(cause.crossings.begin(), cause.crossings.end());
    c.time_event = cause.time_event;
    c.x_before.assign(x.begin(), x.end());
    const auto d = inner_->discrete();
    c.d_before.assign(d.begin(), d.end());
    const runtime::EventResponse r = inner_->handle_event(cause, x, u, p);
    c.x_after.assign(x.begin(), x.end());
    const auto d2 = inner_->discrete();
    c.d_after.assign(d2.begin(), d2.end());
    c.fired = inner_->take_fired_counts();
    calls.push_back(std::move(c));
    return r;
  }
  std::span<double> discrete() override { return inner_->discrete(); }
  std::vector<int> take_fired_counts() override { return inner_->take_fired_counts(); }
  std::string last_failure() const override { return inner_->last_failure(); }
  std::vector<std::string> notes() const override { return inner_->notes(); }

private:
  std::unique_ptr<runtime::Model> inner_;
};

/// The calls of one event instant: [first, last).
struct Instant {
  std::size_t first = 0, last = 0;
};

std::vector<Instant> instants(const std::vector<EventRecorder::Call>& calls) {
  std::vector<Instant> out;
  for (std::size_t k = 0; k < calls.size(); ++k) {
    const auto& c = calls[k];
    const bool fresh = c.time_event || std::any_of(c.crossings.begin(), c.crossings.end(), [](int v) { return v != 0; });
    if (fresh || out.empty() || calls[out.back().first].t != c.t)
      out.push_back({k, k + 1});
    else
      out.back().last = k + 1;
  }
  return out;
}

std::vector<std::size_t> fired_whens(const symbolic::OdeModel& ode, const RelationMap& rel, std::size_t indicator,
                                     int direction) {
  std::vector<std::size_t> out;
  for (std::size_t w = 0; w < ode.whens.size(); ++w)
    for (const auto& e : rel.entries)
      if (e.relation == ode.whens[w].condition && e.indicator == indicator &&
          (direction < 0 ? e.value_if_down : 1.0 - e.value_if_down) == 1.0)
        out.push_back(w);
  return out;
}

std::string indicator_text(const symbolic::OdeModel& ode, std::size_t i) {
  return symbolic::to_modelica(ode.arena, ode.zero_crossings[i]);
}

/// The when-clause of indicator i, if one has it as its condition.
std::optional<std::size_t> when_of(const symbolic::OdeModel& ode, const RelationMap& rel, std::size_t i) {
  for (std::size_t w = 0; w < ode.whens.size(); ++w)
    for (const auto& e : rel.entries)
      if (e.indicator == i && e.relation == ode.whens[w].condition) return w;
  return std::nullopt;
}

PhaseRefusal refusal(const symbolic::OdeModel& ode, const RelationMap& rel, std::size_t indicator,
                     const std::string& message) {
  return {message + " (indicator " + indicator_text(ode, indicator) + ")", when_of(ode, rel, indicator), indicator};
}

/// Zeno and chattering: too many state-event switches, or two switches too
/// close; too many time events.
std::optional<PhaseRefusal> check_switches(const symbolic::OdeModel& ode, const RelationMap& rel,
                                           const std::vector<PhaseSwitch>& sw, std::size_t max_switches,
                                           double min_gap) {
  std::map<std::size_t, std::size_t> count;
  std::size_t timed = 0;
  for (const auto& s : sw) s.timed ? ++timed : ++count[s.indicator];
  if (sw.size() - timed > max_switches) {
    const auto most = std::max_element(count.begin(), count.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    return refusal(ode, rel, most->first,
                   fmt::format("the simulation of the initial guess switches {} times (more than {}; "
                               "chattering or Zeno behaviour?), {} of them here",
                               sw.size() - timed, max_switches, most->second));
  }
  if (timed > kMaxTimedSwitches)
    return PhaseRefusal{fmt::format("the simulation of the initial guess has {} time events that change the model "
                                    "(more than {}): each is a phase of the collocation",
                                    timed, kMaxTimedSwitches),
                        std::nullopt, std::nullopt};
  for (std::size_t k = 1; k < sw.size(); ++k)
    if (sw[k].time - sw[k - 1].time < min_gap) {
      const std::string what = fmt::format("the simulation of the initial guess switches at t = {:.9g} and again "
                                           "{:.3g} later (closer than {:.3g}: chattering or Zeno behaviour?)",
                                           sw[k - 1].time, sw[k].time - sw[k - 1].time, min_gap);
      const PhaseSwitch& s = sw[k].timed ? sw[k - 1] : sw[k];
      if (s.timed) return PhaseRefusal{what, std::nullopt, std::nullopt};
      return refusal(ode, rel, s.indicator, what);
    }
  return std::nullopt;
}

/// The clauses with a count in `fired` (not the every-event ones), in order.
std::vector<std::size_t> fired_clauses(const symbolic::OdeModel& ode, const std::vector<int>& fired) {
  std::vector<std::size_t> out;
  for (std::size_t w = 0; w < fired.size() && w < ode.whens.size(); ++w)
    if (fired[w] > 0 && !ode.whens[w].every_event) out.push_back(w);
  return out;
}

/// The sample() and tick index k of a tick at t with parameters p, if its
/// start and interval are expressions over the parameters.
std::optional<std::pair<std::size_t, double>> tick_at(const symbolic::OdeModel& ode, const std::vector<double>& p,
                                                     double t) {
  for (std::size_t i = 0; i < ode.samples.size(); ++i) {
    const symbolic::Expr roots[] = {ode.samples[i].start, ode.samples[i].interval};
    symbolic::LeafValues values;
    bool parameters = true;
    for (symbolic::Expr leaf : symbolic::leaves(ode.arena, roots)) {
      const bool is_parameter = ode.arena.kind(leaf) == symbolic::ExprKind::Symbol &&
                                ode.arena.symbol_info(leaf).role == symbolic::SymbolRole::Parameter;
      const auto index = is_parameter ? static_cast<std::size_t>(ode.arena.symbol_info(leaf).index) : p.size();
      if (index >= p.size()) {
        parameters = false;
        break;
      }
      values[leaf] = p[index];
    }
    if (!parameters) continue;
    const auto v = symbolic::evaluate(ode.arena, roots, values);
    const double k = std::round((t - v[0]) / v[1]);
    if (k >= 0 && std::abs(v[0] + k * v[1] - t) <= 1e-12 * std::max(1.0, std::abs(t))) return std::pair{i, k};
  }
  return std::nullopt;
}

bool sets_held(const symbolic::OdeModel& ode, const RelationMap& rel, const std::vector<std::size_t>& whens) {
  for (std::size_t w : whens)
    for (const auto& a : ode.whens[w].assignments)
      for (std::size_t j = 0; j < ode.discrete.size(); ++j)
        if (rel.held[j] && ode.discrete[j].symbol == a.target) return true;
  return false;
}

/// Held values set at t0 that the phases cannot take: a clause that fired
/// twice there (at initialisation and at a tick) reading pre() of a held
/// variable, or one that reads a held variable through the equations (the
/// first phase's equations see its value after t0, not before).
std::optional<PhaseRefusal> check_initial_whens(const symbolic::OdeModel& ode, const RelationMap& rel,
                                                const std::vector<int>& fired) {
  for (std::size_t w : fired_clauses(ode, fired)) {
    std::vector<symbolic::Expr> values;
    for (const auto& a : ode.whens[w].assignments) values.push_back(a.value);
    if (!sets_held(ode, rel, {w})) continue;
    const auto direct = symbolic::leaves(ode.arena, values);
    const auto through = leaves_through_steps(ode, values);
    for (std::size_t j = 0; j < ode.discrete.size(); ++j) {
      if (!rel.held[j]) continue;
      const symbolic::Expr d = ode.discrete[j].symbol;
      const auto reads = [&](const std::vector<symbolic::Expr>& v, bool pre) {
        return std::any_of(v.begin(), v.end(), [&](symbolic::Expr e) {
          const bool is_pre = ode.arena.kind(e) == symbolic::ExprKind::Pre;
          return is_pre == pre && (is_pre ? ode.arena.operand(e, 0) == d : e == d);
        });
      };
      const bool twice = fired[w] > 1 && reads(direct, true);
      if (twice || reads(through, true) || reads(through, false))
        return PhaseRefusal{fmt::format("when {}: at t0 it sets a held value from {} of {}, which the "
                                        "multi-phase collocation cannot order",
                                        symbolic::to_modelica(ode.arena, ode.whens[w].condition),
                                        twice ? "pre()" : "the equations' value",
                                        ode.discrete[j].info.name),
                            w, std::nullopt};
    }
  }
  return std::nullopt;
}

/// Signs of the indicators at each mode's midpoint (from a second simulation).
std::string fill_signs(const runtime::Model& model, ModeSequence& seq, const runtime::Inputs& inputs,
                       const std::vector<double>& p, const runtime::SimulationOptions& so) {
  std::vector<double> times{seq.modes.front().start};
  for (const auto& m : seq.modes) times.push_back(0.5 * (m.start + m.end));
  times.push_back(seq.modes.back().end);
  auto sim_model = model.clone();
  const runtime::SimulationResult sim = runtime::simulate(*sim_model, inputs, p, runtime::OutputGrid::at(times), so);
  if (!sim.ok() || sim.trajectory.rows() != times.size()) return sim.message.empty() ? "simulation stopped" : sim.message;
  const runtime::ModelInfo& info = model.info();
  auto eval = model.clone();
  std::vector<double> x0(info.states.size()), u(info.inputs.size()), g(info.num_event_indicators);
  inputs.evaluate(times.front(), u);
  eval->initial_state(times.front(), u, p, x0);
  for (std::size_t k = 0; k < seq.modes.size(); ++k) {
    PhaseMode& m = seq.modes[k];
    const double t = times[k + 1];
    std::vector<double> x(sim.trajectory.row(k + 1).begin(), sim.trajectory.row(k + 1).begin() + x0.size());
    auto d = eval->discrete();
    std::copy_n(m.discrete.begin(), std::min(d.size(), m.discrete.size()), d.begin());
    inputs.evaluate(t, u);
    eval->event_indicators(t, x, u, p, g);
    m.signs.clear();
    for (double v : g) m.signs.push_back(v > 0 ? 1 : v < 0 ? -1 : 0);
  }
  return {};
}

}  // namespace

ModeRecording record_modes(const runtime::Model& model, const symbolic::OdeModel& ode, const RelationMap& rel,
                           const runtime::Inputs& inputs, const std::vector<double>& p, double t0, double tf,
                           std::size_t max_switches, double min_gap) {
  ModeRecording out;
  EventRecorder rec(model.clone());
  runtime::SimulationOptions so;
  so.relative_tolerance = 1e-10;
  so.absolute_tolerance = 1e-10;
  {
    std::vector<double> x0(model.info().states.size()), u0(model.info().inputs.size());
    inputs.evaluate(t0, u0);
    rec.initial_state(t0, u0, p, x0);
  }
  const auto d0 = rec.discrete();
  ModeSequence seq;
  seq.modes.push_back({{}, std::vector<double>(d0.begin(), d0.end()), t0, tf});
  seq.initial_whens = fired_clauses(ode, rec.initial_fired);
  if (auto r = check_initial_whens(ode, rel, rec.initial_fired)) {
    out.refusal = r;
    return out;
  }
  const runtime::SimulationResult sim = runtime::simulate(rec, inputs, p, runtime::OutputGrid::at({t0, tf}), so);
  if (!sim.ok()) {
    out.simulation_failure = sim.message;
    return out;
  }
  for (const Instant& in : instants(rec.calls)) {
    const auto& first = rec.calls[in.first];
    const auto& last = rec.calls[in.last - 1];
    std::vector<std::size_t> crossed;
    for (std::size_t i = 0; i < first.crossings.size(); ++i)
      if (first.crossings[i] != 0) crossed.push_back(i);
    bool in_equations = false;
    for (std::size_t i : crossed) in_equations = in_equations || rel.in_equations[i];
    std::vector<int> fired(ode.whens.size(), 0);
    for (std::size_t k = in.first; k < in.last; ++k)
      for (std::size_t w = 0; w < rec.calls[k].fired.size() && w < fired.size(); ++w) fired[w] += rec.calls[k].fired[w];
    const std::vector<std::size_t> whens = fired_clauses(ode, fired);
    // A clause that sets a held value makes a switch even if the value did
    // not change: under other inputs or parameters it does.
    if (first.x_before == last.x_after && first.d_before == last.d_after && !in_equations &&
        !sets_held(ode, rel, whens))
      continue;
    const bool timed = crossed.empty();
    if (timed && first.t >= tf) break;  // a tick at tf changes nothing on the horizon
    if (timed && !first.time_event) {
      out.refusal = PhaseRefusal{fmt::format("an event at t = {:.9g} changes the model without a crossing or a "
                                             "time event", first.t),
                                 std::nullopt, std::nullopt};
      return out;
    }
    // The sample() flags fall in the iteration after a tick: a time event
    // may change discrete values by event iteration, a state event not.
    for (std::size_t k = in.first + 1; k < in.last; ++k)
      if (rec.calls[k].x_before != rec.calls[k].x_after ||
          (!timed && rec.calls[k].d_before != rec.calls[k].d_after)) {
        const std::string what = fmt::format("the event at t = {:.9g} triggers further changes by event iteration; "
                                             "the multi-phase collocation takes one step per switch", first.t);
        out.refusal = timed ? PhaseRefusal{what, std::nullopt, std::nullopt} : refusal(ode, rel, crossed[0], what);
        return out;
      }
    PhaseSwitch sw;
    sw.time = first.t;
    sw.timed = timed;
    if (timed) sw.tick = tick_at(ode, p, first.t);
    sw.whens = whens;
    if (!timed) {
      sw.indicator = crossed[0];
      sw.direction = first.crossings[crossed[0]];
    }
    for (std::size_t i : crossed) {
      if (i != sw.indicator) sw.also.push_back({i, first.crossings[i]});
      for (std::size_t w : fired_whens(ode, rel, i, first.crossings[i])) sw.whens.push_back(w);
    }
    std::sort(sw.whens.begin(), sw.whens.end());
    sw.whens.erase(std::unique(sw.whens.begin(), sw.whens.end()), sw.whens.end());
    sw.states_after = last.x_after;
    seq.modes.back().end = sw.time;
    seq.modes.push_back({{}, last.d_after, sw.time, tf});
    seq.switches.push_back(std::move(sw));
  }
  if (auto r = check_switches(ode, rel, seq.switches, max_switches, min_gap)) {
    out.refusal = r;
    return out;
  }
  if (auto failure = fill_signs(model, seq, inputs, p, so); !failure.empty()) {
    out.simulation_failure = failure;
    return out;
  }
  out.sequence = std::move(seq);
  return out;
}

bool same_modes(const ModeSequence& a, const ModeSequence& b, const RelationMap& rel) {
  if (a.switches.size() != b.switches.size() || a.modes.size() != b.modes.size()) return false;
  for (std::size_t k = 0; k < a.switches.size(); ++k) {
    const auto &x = a.switches[k], &y = b.switches[k];
    if (x.timed != y.timed || x.indicator != y.indicator || x.direction != y.direction || x.also != y.also ||
        x.whens != y.whens || x.tick != y.tick || (x.timed && !x.tick && x.time != y.time))
      return false;
  }
  if (a.initial_whens != b.initial_whens) return false;
  for (std::size_t k = 0; k < a.modes.size(); ++k) {
    const auto &x = a.modes[k], &y = b.modes[k];
    if (x.discrete.size() != y.discrete.size()) return false;
    for (std::size_t j = 0; j < x.discrete.size(); ++j)
      if (x.discrete[j] != y.discrete[j] && !(j < rel.held.size() && rel.held[j])) return false;
    for (std::size_t i = 0; i < rel.in_equations.size(); ++i)
      if (rel.in_equations[i] && i < x.signs.size() && i < y.signs.size() && x.signs[i] != y.signs[i]) return false;
  }
  return true;
}

}  // namespace mo::tools
