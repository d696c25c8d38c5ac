// Optimal control on a model with events by multi-phase collocation; see study_phases.hpp.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>

#include "mo/runtime/simulate.hpp"
#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/traversal.hpp"
#include "study_events.hpp"
#include "study_internal.hpp"
#include "study_output.hpp"
#include "study_phases.hpp"
#include "study_phases_internal.hpp"
#include "study_plots.hpp"

namespace mo::tools {

using namespace detail;

Guess initial_guess(const runtime::OptimalControlProblem& P) {
  Guess g;
  g.parameters = P.parameters;
  for (const auto& fp : P.free_parameters)
    if (fp.initial_guess) g.parameters[fp.parameter] = *fp.initial_guess;
  for (const auto& c : P.controls) {
    if (c.initial_guess) {
      g.controls.push_back(c.initial_guess);
      continue;
    }
    g.controls.push_back(runtime::constant_input(std::clamp(0.0, c.bounds.lo, c.bounds.hi)));
  }
  return g;
}

runtime::Inputs guess_inputs(const Guess& g, const runtime::OptimalControlProblem& P, std::size_t nu) {
  std::vector<std::unique_ptr<runtime::InputSignal>> signals(nu);
  for (const auto& [input, signal] : P.fixed_inputs) signals[input] = runtime::shared_input(signal);
  for (std::size_t c = 0; c < P.controls.size(); ++c)
    signals[P.controls[c].input] = runtime::shared_input(g.controls[c]);
  return runtime::Inputs(std::move(signals));
}

/// The multi-phase problem on s ∈ [0, 1] for the stacked model.
runtime::OptimalControlProblem phased_problem(const runtime::OptimalControlProblem& P, const PhasedModel& pm,
                                              const ModeSequence& seq, const Guess& g,
                                              const runtime::ModelInfo& base, double min_gap, bool keep_signs) {
  const std::size_t K = pm.phases;
  std::vector<double> guess_times{P.t0};
  for (const auto& b : pm.layout.boundaries) guess_times.push_back(b.time);
  guess_times.push_back(P.tf);
  runtime::OptimalControlProblem Q;
  Q.t0 = 0.0;
  Q.tf = 1.0;
  for (const auto& c : P.controls)
    for (std::size_t k = 0; k < K; ++k) {
      runtime::FreeControl fc = c;
      fc.input = pm.input(k, c.input);
      const std::size_t index = static_cast<std::size_t>(&c - P.controls.data());
      fc.initial_guess = phase_time_signal(g.controls[index], guess_times[k], guess_times[k + 1]);
      Q.controls.push_back(std::move(fc));
    }
  for (const auto& [input, signal] : P.fixed_inputs)
    for (std::size_t k = 0; k < K; ++k)
      Q.fixed_inputs[pm.input(k, input)] = phase_time_signal(signal, guess_times[k], guess_times[k + 1]);
  for (const auto& p : pm.ode.parameters) Q.parameters.push_back(p.value);  // τ_k, φ, q^k guessed
  std::copy(g.parameters.begin(), g.parameters.end(), Q.parameters.begin());
  for (auto fp : P.free_parameters) {
    fp.initial_guess = g.parameters[fp.parameter];
    Q.free_parameters.push_back(fp);
  }
  for (std::size_t k = 0; k < pm.switch_time.size(); ++k)
    if (!seq.switches[k].timed) Q.free_parameters.push_back({pm.switch_time[k], {P.t0, P.tf}, seq.switches[k].time});
  for (std::size_t h : pm.held_parameter) Q.free_parameters.push_back({h, {}, pm.ode.parameters[h].value});
  for (std::size_t o : pm.held_output) Q.point_constraints.push_back({o, 1.0, {0.0, 0.0}});
  for (std::size_t o : pm.held_initial_output) Q.point_constraints.push_back({o, 0.0, {0.0, 0.0}});
  for (const auto& c : pm.continuity) {
    Q.free_parameters.push_back({c.parameter, {}, 0.0});
    Q.point_constraints.push_back({c.before_output, 1.0, {0.0, 0.0}});
    const bool control = std::any_of(P.controls.begin(), P.controls.end(), [&](const runtime::FreeControl& f) { return f.input == c.input; });
    if (control) Q.point_constraints.push_back({c.after_output, 0.0, {0.0, 0.0}});
  }
  for (std::size_t k = 0; k + 1 < K; ++k)
    for (std::size_t i = 0; i < pm.nx; ++i)
      Q.free_parameters.push_back({pm.phase_start[k] + i, {base.states[i].min, base.states[i].max},
                                   pm.layout.boundaries[k].states_after[i]});
  const std::size_t nb = base.num_base_states();
  for (std::size_t k = 0; k < pm.fplus_parameter.size(); ++k)
    for (std::size_t i = 0; i < nb; ++i) Q.free_parameters.push_back({pm.fplus_parameter[k] + i, {}, 0.0});
  for (const auto& [i, b] : P.state_bounds)
    for (std::size_t k = 0; k < K; ++k) Q.state_bounds[pm.state(k, i)] = b;
  for (const auto& m : P.mayer) Q.mayer.push_back({pm.output(K - 1, m.output), m.weight});
  if (!P.lagrange.empty()) {
    if (P.lagrange.size() != 1 || !pm.lagrange_output) throw std::logic_error("multi-phase: one integrand expected");
    Q.lagrange.push_back({*pm.lagrange_output, P.lagrange.front().weight});
  }
  for (const auto& c : P.path_constraints)
    for (std::size_t k = 0; k < K; ++k) Q.path_constraints.push_back({pm.output(k, c.output), c.bounds});
  for (const auto& c : P.point_constraints) {
    if (c.time == P.tf)
      Q.point_constraints.push_back({pm.output(K - 1, c.output), 1.0, c.bounds});
    else if (c.time == P.t0)
      Q.point_constraints.push_back({pm.output(0, c.output), 0.0, c.bounds});
    else
      throw UsageError(fmt::format("a constraint at t = {} inside the horizon of a model with events: the "
                                   "multi-phase collocation takes point constraints at startTime and "
                                   "finalTime only", c.time));
  }
  for (const auto& f : P.final_state) Q.final_state.push_back({pm.state(K - 1, f.state), f.bounds});
  for (std::size_t o : pm.indicator_output) Q.point_constraints.push_back({o, 1.0, {0.0, 0.0}});
  for (std::size_t k = 0; k + 1 < K; ++k)
    for (std::size_t i = 0; i < pm.nx; ++i) Q.point_constraints.push_back({pm.jump_output[k] + i, 1.0, {0.0, 0.0}});
  for (std::size_t o : pm.length_output) Q.path_constraints.push_back({o, {min_gap, runtime::Bounds{}.hi}});
  for (std::size_t k = 0; k < pm.fplus_output.size(); ++k) {  // φ = der(x) at the start of the next phase
    for (std::size_t i = 0; i < nb; ++i) Q.point_constraints.push_back({pm.fplus_output[k] + i, 0.0, {0.0, 0.0}});
  }
  for (std::size_t k = 0; k < pm.input_parameter.size(); ++k)  // the input continuous at a switch
    for (std::size_t j = 0; j < pm.nu; ++j) {
      Q.free_parameters.push_back({pm.input_parameter[k] + j, {}, 0.0});
      Q.point_constraints.push_back({pm.input_before_output[k] + j, 1.0, {0.0, 0.0}});
      const bool control = std::any_of(P.controls.begin(), P.controls.end(), [&](const runtime::FreeControl& c) { return c.input == j; });
      if (control) Q.point_constraints.push_back({pm.input_after_output[k] + j, 0.0, {0.0, 0.0}});
    }
  if (keep_signs)
    for (std::size_t o : pm.sign_output) Q.path_constraints.push_back({o, {0.0, runtime::Bounds{}.hi}});
  Q.collocation = P.collocation;
  Q.solver = P.solver;
  return Q;
}

namespace {

/// A timed switch's time at the solution: its tick's start + k·interval at
/// the solved parameters, or `fixed` for a tick that does not move.
double solved_tick_time(const PhasedModel& pm, const runtime::OptimizationResult& r, std::size_t sw, double fixed) {
  const symbolic::Expr tau = pm.tick_time[sw];
  if (!tau.valid()) return fixed;
  symbolic::LeafValues values;
  for (symbolic::Expr leaf : symbolic::leaves(pm.ode.arena, {&tau, 1})) {
    const auto index = static_cast<std::size_t>(pm.ode.arena.symbol_info(leaf).index);
    values[leaf] = index < r.parameters.size() ? r.parameters[index] : pm.ode.parameters[index].value;
  }
  return symbolic::evaluate(pm.ode.arena, {&tau, 1}, values).front();
}

}  // namespace

/// The phases' boundaries τ_0 = t0 < τ_1 < ... < τ_K = tf at the solution.
std::vector<double> boundary_times(const PhasedModel& pm, const runtime::OptimizationResult& r, double t0, double tf) {
  std::vector<double> taus{t0};
  for (const auto& b : pm.layout.boundaries) {
    if (b.switch_index && pm.timed_switch[*b.switch_index]) {
      taus.push_back(solved_tick_time(pm, r, *b.switch_index, b.time));
      continue;
    }
    if (!b.switch_index) {
      taus.push_back(b.time);
      continue;
    }
    const std::size_t p = pm.switch_time[*b.switch_index];
    taus.push_back(p < r.parameters.size() ? r.parameters[p] : std::nan(""));
  }
  taus.push_back(tf);
  return taus;
}

/// The switching times at the solution, one per switch.
std::vector<double> solved_switch_times(const PhasedModel& pm, const runtime::OptimizationResult& r) {
  std::vector<double> out;
  for (std::size_t k = 0; k < pm.switch_time.size(); ++k) {
    const std::size_t p = pm.switch_time[k];
    const double guess = pm.ode.parameters[p].value;
    out.push_back(pm.timed_switch[k] ? solved_tick_time(pm, r, k, guess)
                  : p < r.parameters.size() ? r.parameters[p]
                                            : std::nan(""));
  }
  return out;
}

/// The solution on physical time for the base model: trajectories, element
/// times and controls of all phases in sequence. A solve that ended before
/// it had a solution (an invalid problem) gives its status and message only.
runtime::OptimizationResult physical_result(const PhasedModel& pm, const runtime::OptimizationResult& r,
                                            const std::vector<double>& taus, const runtime::ModelInfo& base,
                                            std::size_t num_controls) {
  runtime::OptimizationResult R;
  R.status = r.status;
  R.message = r.message;
  R.retries = r.retries;
  R.objective = r.objective;
  R.iterations = r.iterations;
  R.kkt = r.kkt;
  R.size = r.size;
  R.timings = r.timings;
  R.parameters.assign(r.parameters.begin(), r.parameters.begin() + static_cast<std::ptrdiff_t>(std::min(pm.np, r.parameters.size())));
  std::vector<std::string> names;
  for (const auto& x : base.states) names.push_back(x.name);
  for (const auto& u : base.inputs) names.push_back(u.name);
  R.trajectories = runtime::ResultTable(names);
  if (r.trajectories.rows() == 0 || r.control_values.size() < num_controls * pm.phases) return R;
  std::vector<double> row(pm.nx + pm.nu);
  for (std::size_t k = 0; k < pm.phases; ++k) {
    const double len = taus[k + 1] - taus[k];
    for (std::size_t j = 0; j < r.trajectories.rows(); ++j) {
      const auto values = r.trajectories.row(j);
      for (std::size_t i = 0; i < pm.nx; ++i) row[i] = values[pm.state(k, i)];
      for (std::size_t i = 0; i < pm.nu; ++i) row[pm.nx + i] = values[pm.nx * pm.phases + pm.input(k, i)];
      R.trajectories.add_row(taus[k] + len * r.trajectories.times()[j], row);
    }
    for (std::size_t e = 0; e + 1 < r.element_times.size(); ++e) R.element_times.push_back(taus[k] + len * r.element_times[e]);
  }
  R.element_times.push_back(taus.back());
  for (std::size_t c = 0; c < num_controls; ++c) {
    std::vector<double> values;
    for (std::size_t k = 0; k < pm.phases; ++k) {
      const auto& v = r.control_values[c * pm.phases + k];
      values.insert(values.end(), v.begin(), v.end());
    }
    R.control_values.push_back(std::move(values));
  }
  return R;
}


double state_scale(const runtime::OptimizationResult& R, const runtime::ModelInfo& info, std::size_t i) {
  double scale = info.states[i].nominal;
  for (std::size_t j = 0; j < R.trajectories.rows(); ++j) scale = std::max(scale, std::abs(R.trajectories.at(j, i)));
  return scale;
}

/// The collocation's times for the re-simulation: a time within rounding of
/// the one before it (phases meet at t = τ_k + 1·(τ_{k+1} − τ_k) and
/// τ_{k+1} + 0·…, computed apart) is made equal to it, which the simulator
/// takes as a repeated output; two distinct times 1e-16 apart it refuses.
std::vector<double> output_times(const runtime::OptimizationResult& R, const runtime::OptimalControlProblem& P) {
  std::vector<double> t = R.trajectories.times();
  const double close = 1e-12 * (P.tf - P.t0);
  for (std::size_t j = 1; j < t.size(); ++j)
    if (std::abs(t[j] - t[j - 1]) <= close) t[j] = t[j - 1];
  return t;
}

EventCheck check_resimulation(runtime::Model& model, const symbolic::OdeModel& ode, const RelationMap& rel,
                              const ModeSequence& seq, const runtime::OptimalControlProblem& Pphys,
                              runtime::OptimizationResult& R, const std::vector<double>& switches, double min_gap) {
  EventCheck c;
  const runtime::ModelInfo& info = model.info();
  if (R.element_times.size() < 2 ||
      std::adjacent_find(R.element_times.begin(), R.element_times.end(), std::greater_equal<>()) != R.element_times.end()) {
    c.failure = "the solution's phases do not follow each other in time (a switching time out of order)";
    R.check.message = c.failure;
    return c;
  }
  const runtime::Inputs inputs = runtime::optimal_inputs(Pphys, R, info.inputs.size());
  ModeRecording rec = record_modes(model, ode, rel, inputs, R.parameters, Pphys.t0, Pphys.tf, 10 * kMaxSwitches, 0.0);
  if (!rec.sequence) {
    c.failure = !rec.simulation_failure.empty() ? rec.simulation_failure : rec.refusal->message;
    R.check.message = c.failure;
    return c;
  }
  c.modes = rec.sequence;
  c.same_modes = same_modes(seq, *rec.sequence, rel);
  if (c.same_modes)
    for (std::size_t k = 0; k < seq.switches.size(); ++k)
      c.max_switch_shift = std::max(c.max_switch_shift, std::abs(rec.sequence->switches[k].time - switches[k]));
  runtime::SimulationOptions so;
  so.relative_tolerance = 1e-10;
  so.absolute_tolerance = 1e-10;
  if (info.num_base_states() < info.states.size())  // sensitivity states: with their jumps at the events
    so.sensitivities.method = runtime::SensitivityMethod::model_states;
  auto sim_model = model.clone();
  const auto sim = runtime::simulate(*sim_model, inputs, R.parameters, runtime::OutputGrid::at(output_times(R, Pphys)), so);
  R.check.performed = sim.ok();
  R.check.message = sim.message;
  R.check.resimulated = runtime::ResultTable(R.trajectories.names());
  const double window = std::max(min_gap, 10.0 * c.max_switch_shift);
  std::vector<double> near = switches;
  if (c.modes)
    for (const auto& sw : c.modes->switches) near.push_back(sw.time);
  std::vector<double> scales;
  for (std::size_t i = 0; i < info.states.size(); ++i) scales.push_back(state_scale(R, info, i));
  const std::size_t nx = info.states.size(), nu = info.inputs.size();
  std::vector<double> row(nx + nu);
  for (std::size_t j = 0; j < sim.trajectory.rows() && j < R.trajectories.rows(); ++j) {
    const double t = sim.trajectory.times()[j];
    std::copy_n(sim.trajectory.row(j).begin(), nx, row.begin());
    inputs.evaluate(t, std::span<double>(row).subspan(nx));
    R.check.resimulated.add_row(t, row);
    const bool at_switch = std::any_of(near.begin(), near.end(), [&](double s) { return std::abs(t - s) <= window; });
    if (at_switch) continue;
    for (std::size_t i = 0; i < nx; ++i) {
      const double diff = std::abs(sim.trajectory.at(j, i) - R.trajectories.at(j, i));
      if (diff / scales[i] > c.max_relative) {
        c.max_relative = diff / scales[i];
        R.check.max_state_difference = diff;
        R.check.worst_state = info.states[i].name;
        R.check.worst_state_time = t;
      }
    }
  }
  if (!sim.ok()) c.failure = sim.message;
  return c;
}

std::string describe_modes(const symbolic::OdeModel& ode, const ModeSequence& seq) {
  std::string out;
  std::size_t ticks = 0;
  double first_tick = 0.0, last_tick = 0.0;
  for (const auto& sw : seq.switches) {
    if (sw.timed) {  // summarised: a sampled controller has many
      first_tick = ticks++ == 0 ? sw.time : first_tick;
      last_tick = sw.time;
      continue;
    }
    out += fmt::format("{}{} {} at t = {:.6g}", out.empty() ? "" : ", ", symbolic::to_modelica(ode.arena, ode.zero_crossings[sw.indicator]),
                       sw.direction < 0 ? "falls through 0" : "rises through 0", sw.time);
    for (const auto& [i, direction] : sw.also)
      out += fmt::format(" with {} {}", symbolic::to_modelica(ode.arena, ode.zero_crossings[i]),
                         direction < 0 ? "falling" : "rising");
  }
  if (ticks > 0)
    out += fmt::format("{}{} time event{} from t = {:.6g} to {:.6g}", out.empty() ? "" : ", ", ticks,
                       ticks == 1 ? "" : "s", first_tick, last_tick);
  return out.empty() ? "no switch" : out;
}

nlohmann::json sequence_json(const symbolic::OdeModel& ode, const ModeSequence& seq) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& sw : seq.switches) {
    nlohmann::json whens = nlohmann::json::array();
    for (std::size_t w : sw.whens) whens.push_back("when " + symbolic::to_modelica(ode.arena, ode.whens[w].condition));
    nlohmann::json also = nlohmann::json::array();
    for (const auto& [i, direction] : sw.also)
      also.push_back({{"indicator", symbolic::to_modelica(ode.arena, ode.zero_crossings[i])},
                      {"direction", direction < 0 ? "down" : "up"}});
    if (sw.timed) {
      a.push_back({{"time", sw.time}, {"time_event", true}, {"when_clauses", whens}});
      continue;
    }
    a.push_back({{"time", sw.time},
                 {"indicator", symbolic::to_modelica(ode.arena, ode.zero_crossings[sw.indicator])},
                 {"direction", sw.direction < 0 ? "down" : "up"},
                 {"when_clauses", whens},
                 {"crossing_with_it", also}});
  }
  return a;
}

int refuse_phases(const frontend::flat::Model& flat, const PhaseRefusal& r, frontend::DiagnosticEngine& diags) {
  // Printed alone: the lowering's warnings are on stderr already.
  std::cerr << diags.format(diags.report(
      frontend::DiagId::BadOptimization, event_source(flat, r.when),
      r.message + "; the multi-phase collocation of studies on models with events refuses it (docs/events.md)"));
  return 1;
}

std::string event_status(const runtime::OptimizationResult& R, const EventCheck& check, bool same, double time_tol,
                         double state_tol) {
  const bool times_hold = check.max_switch_shift <= time_tol;
  return !R.ok()                                     ? std::string(runtime::to_string(R.status))
         : !check.failure.empty() || !check.modes    ? "resimulation_failed"
         : !same                                     ? "mode_sequence_changed"
         : !times_hold || check.max_relative > state_tol ? "resimulation_mismatch"
                                                         : std::string(runtime::to_string(R.status));
}

nlohmann::json events_json(const symbolic::OdeModel& ode, const ModeSequence& seq, const EventCheck& check,
                           std::size_t phases, int attempt, const std::vector<double>& switches, bool same,
                           double time_tol, double state_tol) {
  return {{"phases", phases},
          {"attempts", attempt},
          {"mode_sequence", sequence_json(ode, seq)},
          {"switch_times", switches},
          {"resimulated_mode_sequence", check.modes ? sequence_json(ode, *check.modes) : nlohmann::json()},
          {"mode_sequence_held", same},
          {"max_switch_time_difference", check.max_switch_shift},
          {"switch_time_tolerance", time_tol},
          {"max_relative_state_difference", check.max_relative},
          {"state_tolerance", state_tol}};
}

int optimal_control_with_events(frontend::flat::Model& flat, const StudyCli& cli, StudyOptions opt,
                                ProblemOutputs problem, symbolic::OdeModel& ode, frontend::DiagnosticEngine& diags) {
  if (problem.free_final_time)
    throw UsageError("a free finalTime on a model with events is not supported (docs/events.md)");
  const RelationMap rel = match_relations(ode);
  if (auto r = check_event_constructs(ode, rel)) return refuse_phases(flat, *r, diags);
  Study s{flat, cli, std::move(opt), std::move(problem), build_model(ode, cli.jobs, "morun", cli.run, cli.quiet)};
  const runtime::ModelInfo& info = s.info();
  const runtime::OptimalControlProblem P = base_problem(s);
  const double min_gap = 1e-6 * (P.tf - P.t0);
  std::optional<std::size_t> lagrange;
  if (!P.lagrange.empty()) lagrange = P.lagrange.front().output;
  Guess guess = initial_guess(P);
  runtime::OptimizationResult R;
  runtime::OptimalControlProblem Pphys = P;
  for (auto& c : Pphys.controls) c.blocking_factors.clear();
  std::string status;
  nlohmann::json events;
  for (int attempt = 1; attempt <= kMaxAttempts; ++attempt) {
    const runtime::Inputs inputs = guess_inputs(guess, P, info.inputs.size());
    ModeRecording rec = record_modes(*s.built.model, ode, rel, inputs, guess.parameters, P.t0, P.tf, kMaxSwitches, min_gap);
    if (rec.refusal) return refuse_phases(flat, *rec.refusal, diags);
    if (!rec.sequence) {
      std::cerr << "morun: error: the simulation of the guess failed: " << rec.simulation_failure << "\n";
      return 1;
    }
    const ModeSequence& seq = *rec.sequence;
    std::cerr << fmt::format("morun: events: {} phase{} ({})\n", seq.modes.size(), seq.modes.size() == 1 ? "" : "s",
                             describe_modes(ode, seq));
    PhasedModel pm = build_phased_model(ode, rel, seq, phase_layout(seq), P.t0, P.tf, lagrange);
    BuiltModel built = build_model(pm.ode, cli.jobs, "morun", cli.run, cli.quiet);
    const runtime::OptimalControlProblem Q = phased_problem(P, pm, seq, guess, info, min_gap);
    runtime::OptimizationResult r;
    {
      PhaseScope phase(cli.run, "solve", fmt::format("optimal control, {} phases", pm.phases));
      r = runtime::solve(*built.model, Q);
    }
    move_to_simulate(cli.run, r.timings.resimulation);
    const std::vector<double> taus = boundary_times(pm, r, P.t0, P.tf);
    const std::vector<double> switches = solved_switch_times(pm, r);
    R = physical_result(pm, r, taus, info, P.controls.size());
    if (R.trajectories.rows() == 0) {
      std::cerr << "morun: error: the optimisation ended without a solution: " << runtime::to_string(R.status) << ": "
                << R.message << "\n";
      return 1;
    }
    Pphys.collocation.n_e = static_cast<int>(R.element_times.size()) - 1;
    EventCheck check = check_resimulation(*s.built.model, ode, rel, seq, Pphys, R, switches, min_gap);
    status = event_status(R, check, check.same_modes, kTimeTolerance * (P.tf - P.t0), kStateTolerance);
    events = events_json(ode, seq, check, pm.phases, attempt, switches, check.same_modes, kTimeTolerance * (P.tf - P.t0),
                         kStateTolerance);
    std::cerr << fmt::format("morun: attempt {}: {}; re-simulated: {}, largest state difference {:.3g} of scale\n",
                             attempt, runtime::to_string(R.status),
                             check.modes ? describe_modes(ode, *check.modes) : check.failure, check.max_relative);
    if (status != "mode_sequence_changed" || attempt == kMaxAttempts) break;
    guess.parameters = R.parameters;  // start again from the optimum, on the new sequence
    for (std::size_t c = 0; c < P.controls.size(); ++c) {
      std::vector<double> starts(R.element_times.begin(), R.element_times.end() - 1);
      guess.controls[c] = runtime::piecewise_constant_input(starts, R.control_values[c]);
    }
  }
  nlohmann::json extra = {{"status", status}, {"events", events}};
  write_optimization_outputs(cli.output, info, Pphys, R, extra);
  if ((s.opt.plot || cli.plot) && R.trajectories.rows() > 0)
    plot_optimization(cli.output, info, Pphys, s.problem, fmt::format("optimal control ({} phases)", events["phases"].get<std::size_t>()));
  std::cerr << fmt::format("morun: optimal control {}: objective {:.6g} after {} iterations\n", status, R.objective,
                           R.iterations);
  if (!R.message.empty()) std::cerr << "morun: " << R.message << "\n";
  return status == "success" || status == "acceptable" ? 0 : 1;
}

}  // namespace mo::tools
