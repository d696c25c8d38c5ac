// The mode sequence of a simulation; see study_phases.hpp.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "mo/runtime/simulate.hpp"
#include "mo/symbolic/printer.hpp"
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
  };

  explicit EventRecorder(std::unique_ptr<runtime::Model> inner) : inner_(std::move(inner)) {}

  std::vector<Call> calls;

  const runtime::ModelInfo& info() const override { return inner_->info(); }
  std::unique_ptr<Model> clone() const override { return std::make_unique<EventRecorder>(inner_->clone()); }
  using Model::initial_state;
  void initial_state(double t0, std::span<const double> u0, std::span<const double> p,
                     std::span<double> x0) override {
    inner_->initial_state(t0, u0, p, x0);
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
    calls.push_back(std::move(c));
    return r;
  }
  std::span<double> discrete() override { return inner_->discrete(); }
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

/// Zeno and chattering: too many switches, or two too close.
std::optional<PhaseRefusal> check_switches(const symbolic::OdeModel& ode, const RelationMap& rel,
                                           const std::vector<PhaseSwitch>& sw, std::size_t max_switches,
                                           double min_gap) {
  if (sw.size() > max_switches) {
    std::map<std::size_t, std::size_t> count;
    for (const auto& s : sw) ++count[s.indicator];
    const auto most = std::max_element(count.begin(), count.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    return refusal(ode, rel, most->first,
                   fmt::format("the simulation of the initial guess switches {} times (more than {}; "
                               "chattering or Zeno behaviour?), {} of them here",
                               sw.size(), max_switches, most->second));
  }
  for (std::size_t k = 1; k < sw.size(); ++k)
    if (sw[k].time - sw[k - 1].time < min_gap)
      return refusal(ode, rel, sw[k].indicator,
                     fmt::format("the simulation of the initial guess switches at t = {:.9g} and again "
                                 "{:.3g} later (closer than {:.3g}: chattering or Zeno behaviour?)",
                                 sw[k - 1].time, sw[k].time - sw[k - 1].time, min_gap));
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
    if (first.x_before == last.x_after && first.d_before == last.d_after && !in_equations) continue;
    if (first.time_event || crossed.empty()) {
      out.refusal = PhaseRefusal{fmt::format("a time event at t = {:.9g} changes the model; the multi-phase "
                                             "collocation takes state events only", first.t),
                                 std::nullopt, std::nullopt};
      return out;
    }
    for (std::size_t k = in.first + 1; k < in.last; ++k)
      if (rec.calls[k].x_before != rec.calls[k].x_after || rec.calls[k].d_before != rec.calls[k].d_after) {
        out.refusal = refusal(ode, rel, crossed[0],
                              fmt::format("the event at t = {:.9g} triggers further changes by event "
                                          "iteration; the multi-phase collocation takes one step per switch",
                                          first.t));
        return out;
      }
    PhaseSwitch sw;
    sw.time = first.t;
    sw.indicator = crossed[0];
    sw.direction = first.crossings[crossed[0]];
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
    if (x.indicator != y.indicator || x.direction != y.direction || x.also != y.also || x.whens != y.whens)
      return false;
  }
  for (std::size_t k = 0; k < a.modes.size(); ++k) {
    const auto &x = a.modes[k], &y = b.modes[k];
    if (x.discrete != y.discrete) return false;
    for (std::size_t i = 0; i < rel.in_equations.size(); ++i)
      if (rel.in_equations[i] && i < x.signs.size() && i < y.signs.size() && x.signs[i] != y.signs[i]) return false;
  }
  return true;
}

}  // namespace mo::tools
