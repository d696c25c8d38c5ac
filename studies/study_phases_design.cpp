// Input design on a model with events by multi-phase collocation; see study_phases.hpp.
//
// The phases are those of the estimation (a switch is a phase boundary with a
// free time, every measurement time a fixed cut), so every sample is the
// value at the end of a phase. The stacked model carries the base model's
// sensitivity states per phase; at a switch they jump by the event's jump
// conditions (study_phases_model.cpp), at a cut they are continuous. Each
// sample and its sensitivities become outputs of the stacked model, and the
// runtime's design (lifted Fisher, exact Hessians) sees them as one
// measurement at s = 1. Path constraints sign·g ≥ 0 keep every phase in its
// mode; the optimum is re-simulated through its events and its Fisher matrix
// recomputed from CVODES sensitivities with the jumps.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "mo/runtime/simulate.hpp"
#include "mpi_world.hpp"
#include "study_internal.hpp"
#include "study_output.hpp"
#include "study_phases.hpp"
#include "study_phases_internal.hpp"
#include "study_plots.hpp"

namespace mo::tools {

using namespace detail;

namespace {

runtime::DesignCriterion criterion_of(const std::string& c) {
  if (c == "A") return runtime::DesignCriterion::A;
  if (c == "D") return runtime::DesignCriterion::D;
  if (c == "E") return runtime::DesignCriterion::E;
  return runtime::DesignCriterion::T;
}

std::size_t base_output(const symbolic::OdeModel& ode, const std::string& name) {
  for (std::size_t o = 0; o < ode.outputs.size(); ++o)
    if (ode.outputs[o].info.name == name) return o;
  throw UsageError("design on a model with events: no output '" + name + "'");
}

/// Adds per sample time and measured output the sample and its sensitivities
/// to J as outputs of the stacked model ("$sampleK.y", "d($sampleK.y)/d(p)");
/// returns the measurement of them all at s = 1.
runtime::MeasurementDesign add_samples(PhasedModel& pm, const symbolic::OdeModel& base,
                                       const runtime::MeasurementDesign& m, const std::vector<std::size_t>& J,
                                       double t0) {
  std::vector<double> ends;  // the end time of each phase that ends at a fixed cut
  for (const auto& b : pm.layout.boundaries) ends.push_back(fixed_end_time(pm, b));
  ends.push_back(m.times.empty() ? t0 : std::max(m.times.back(), ends.empty() ? t0 : ends.back()));
  runtime::MeasurementDesign out;
  out.times = {1.0};
  for (std::size_t k = 0; k < m.times.size(); ++k) {
    const auto phase = phase_ending_at(ends, m.times[k]);
    if (m.times[k] <= t0 || phase == ends.end())
      throw UsageError(fmt::format("design on a model with events: no phase ends at the measurement time {} "
                                   "(measurement times must lie in (startTime, finalTime])", m.times[k]));
    const auto p = static_cast<std::size_t>(phase - ends.begin());
    for (std::size_t r = 0; r < m.outputs.size(); ++r) {
      const std::string y = base.outputs[m.outputs[r]].info.name, name = fmt::format("$sample{}.{}", k + 1, y);
      symbolic::OdeOutput sample;
      sample.info.name = name;
      sample.value = pm.ode.outputs[pm.output(p, m.outputs[r])].value;
      out.outputs.push_back(pm.ode.outputs.size());
      out.sigma.push_back(m.sigma[r]);
      pm.ode.outputs.push_back(std::move(sample));
      for (std::size_t j : J) {
        const std::string pname = base.parameters[j].info.name;
        symbolic::OdeOutput s;
        s.info.name = "d(" + name + ")/d(" + pname + ")";
        s.value = pm.ode.outputs[pm.output(p, base_output(base, "d(" + y + ")/d(" + pname + ")"))].value;
        pm.ode.outputs.push_back(std::move(s));
      }
    }
  }
  return out;
}

/// What stays the same from one start of a multi-phase design to the next.
struct EventDesignSetup {
  const RelationMap& rel;
  runtime::OptimalControlProblem P;      ///< the base problem on physical time
  runtime::OptimalControlProblem Pphys;  ///< P without blocking factors: the result's grid
  std::vector<std::size_t> J;            ///< designed parameters
  runtime::MeasurementDesign m;
  runtime::DesignCriterion crit = runtime::DesignCriterion::T;
  double min_gap = 0, time_tol = 0;
  std::optional<std::size_t> lagrange;
};

/// Solves the multi-phase design from `guess`: records the guess's modes,
/// builds and solves the phased problem, re-simulates, and solves again with
/// the re-simulated mode sequence while it changes (kMaxAttempts solves).
/// `isolated` (a forked multistart worker): no progress line, Ipopt's log to `log_file`.
EventDesignRun solve_event_design(const Study& s, symbolic::OdeModel& ode, const EventDesignSetup& e, Guess guess,
                                  const std::string& log_file, bool isolated) {
  const runtime::ModelInfo& info = s.info();
  const runtime::OptimalControlProblem& P = e.P;
  RunContext* run = isolated ? nullptr : s.cli.run;
  EventDesignRun out;
  std::map<std::size_t, double> moved;
  for (int attempt = 1; attempt <= kMaxAttempts; ++attempt) {
    const runtime::Inputs inputs = guess_inputs(guess, P, info.inputs.size());
    ModeRecording rec =
        record_modes(*s.built.model, ode, e.rel, inputs, guess.parameters, P.t0, P.tf, kMaxSwitches, e.min_gap);
    if (rec.refusal) {
      out.refusal = rec.refusal;
      return out;
    }
    if (!rec.sequence) {
      out.error = "the simulation of the guess failed: " + rec.simulation_failure;
      return out;
    }
    ModeSequence seq = *rec.sequence;
    for (const auto& [k, t] : moved)
      if (k < seq.switches.size()) seq.switches[k].time = t;
    moved.clear();
    std::string why;
    auto layout = sample_layout(*s.built.model, seq, e.m.times, inputs, guess.parameters, P.t0, P.tf, e.min_gap, why);
    if (!layout) {
      out.error = "design on a model with events: " + why;
      return out;
    }
    PhasedModel pm = build_phased_model(ode, e.rel, seq, *layout, P.t0, P.tf, e.lagrange);
    runtime::InputDesignProblem d;
    d.parameters = e.J;
    d.criterion = e.crit;
    d.measurements = add_samples(pm, ode, e.m, e.J, P.t0);
    std::cerr << fmt::format("morun: events: {} modes ({}), {} phases cut at the measurement times\n",
                             seq.modes.size(), describe_modes(ode, seq), pm.phases);
    BuiltModel built = build_model(pm.ode, s.cli.jobs, "morun", run, s.cli.quiet || isolated);
    runtime::OptimalControlProblem Pk = P;
    Pk.collocation.n_e = std::max(2, (P.collocation.n_e + static_cast<int>(pm.phases) - 1) / static_cast<int>(pm.phases));
    d.ocp = phased_problem(Pk, pm, seq, guess, info, e.min_gap, true);
    d.ocp.solver.log_file = log_file.empty() ? d.ocp.solver.log_file : log_file;
    if (isolated) d.ocp.solver.progress = nullptr;
    runtime::InputDesignResult r;
    {
      PhaseScope phase(run, "solve", fmt::format("input design, {} phases", pm.phases));
      r = runtime::design_input(*built.model, d);
    }
    move_to_simulate(run, r.optimization.timings.resimulation);
    const std::vector<double> taus = boundary_times(pm, r.optimization, P.t0, P.tf);
    const std::vector<double> switches = solved_switch_times(pm, r.optimization);
    out.result.optimization = physical_result(pm, r.optimization, taus, info, P.controls.size());
    runtime::OptimizationResult& R = out.result.optimization;
    if (R.trajectories.rows() == 0) {
      out.error = fmt::format("the design ended without a solution: {}: {}", runtime::to_string(R.status), R.message);
      return out;
    }
    runtime::OptimalControlProblem Pphys = e.Pphys;
    Pphys.collocation.n_e = static_cast<int>(R.element_times.size()) - 1;
    EventCheck check = check_resimulation(*s.built.model, ode, e.rel, seq, Pphys, R, switches, e.min_gap);
    const bool same = check.same_modes && check.modes &&
                      interleaving(*check.modes, e.m.times, P.t0) == interleaving(seq, e.m.times, P.t0);
    out.status = event_status(R, check, same, e.time_tol, kStateTolerance);
    out.events = events_json(ode, seq, check, pm.phases, attempt, switches, same, e.time_tol, kStateTolerance);
    out.result.attempts = r.attempts;
    out.result.fisher_collocation = r.fisher_collocation;
    out.result.information_collocation = r.information_collocation;
    out.result.information_resimulated = std::nan("");
    out.result.fisher_resimulated.resize(0, 0);
    if (R.parameters.size() == info.parameters.size() && check.modes) {  // check.modes: the phases ascend
      try {
        out.result.fisher_resimulated = runtime::fisher_information(
            *s.built.model, runtime::optimal_inputs(Pphys, R, info.inputs.size()), R.parameters, P.t0, e.m, e.J);
        out.result.information_resimulated = runtime::criterion_information(e.crit, out.result.fisher_resimulated);
      } catch (const std::runtime_error& ex) {
        R.check.message += std::string(" (Fisher replay: ") + ex.what() + ")";
      }
    }
    std::cerr << fmt::format("morun: attempt {}: {}; re-simulated: {}, largest state difference {:.3g} of scale\n",
                             attempt, runtime::to_string(R.status),
                             check.modes ? describe_modes(ode, *check.modes) : check.failure, check.max_relative);
    if (!R.message.empty()) std::cerr << "morun: " << R.message << "\n";
    if (out.status == "success" || out.status == "acceptable") {
      moved = stuck_switches(switches, pm.timed_switch, e.m.times, P.t0, P.tf, 10 * e.min_gap);
      if (!moved.empty()) out.status = "switch_at_sample_time";
    }
    if ((out.status != "mode_sequence_changed" && out.status != "switch_at_sample_time") || attempt == kMaxAttempts)
      break;
    if (R.parameters.size() == info.parameters.size()) guess.parameters = R.parameters;
    for (std::size_t c = 0; c < P.controls.size() && check.modes; ++c) {
      std::vector<double> starts(R.element_times.begin(), R.element_times.end() - 1);
      guess.controls[c] = runtime::piecewise_constant_input(starts, R.control_values[c]);
    }
  }
  return out;
}

}  // namespace

int design_with_events(frontend::flat::Model& flat, const StudyCli& cli, StudyOptions opt, ProblemOutputs problem,
                       symbolic::OdeModel& ode, frontend::DiagnosticEngine& diags) {
  if (problem.free_final_time)
    throw UsageError("a free finalTime on a model with events is not supported (docs/events.md)");
  const RelationMap rel = match_relations(ode);
  if (auto r = check_event_constructs(ode, rel)) return refuse_phases(flat, *r, diags);
  Study s{flat, cli, std::move(opt), std::move(problem), build_model(ode, cli.jobs, "morun", cli.run, cli.quiet)};
  const runtime::ModelInfo& info = s.info();
  EventDesignSetup e{rel, base_problem(s), {}, {}, {}, criterion_of(s.opt.criterion), 0, 0, std::nullopt};
  const runtime::OptimalControlProblem& P = e.P;
  for (const auto& name : s.opt.parameters) e.J.push_back(parameter_index(info, name));
  e.m = measurements(s, P.t0, P.tf);
  e.min_gap = 1e-6 * (P.tf - P.t0);
  e.time_tol = kTimeTolerance * (P.tf - P.t0);
  if (!P.lagrange.empty()) e.lagrange = P.lagrange.front().output;
  e.Pphys = P;
  for (auto& c : e.Pphys.controls) c.blocking_factors.clear();
  const std::vector<DesignStart> starts = design_starts(s.opt, P, info);
  const MultistartSettings settings{s.cli.jobs, s.cli.output, s.opt.cluster_tol, s.cli.run};
  auto guess_of = [&](const DesignStart& start) {
    Guess g = initial_guess(P);
    for (std::size_t c = 0; c < g.controls.size() && c < start.guesses.size(); ++c)
      if (start.guesses[c]) g.controls[c] = start.guesses[c];
    return g;
  };
  EventDesignRun best;
  std::optional<MultistartResult> multi;
  if (starts.size() > 1) {
    multi = event_design_multistart(starts, settings, [&](std::size_t k, const std::string& log, bool isolated) {
      return solve_event_design(s, ode, e, guess_of(starts[k]), log, isolated);
    }, best);
    if (!multi) return 0;  // an MPI rank other than 0: rank 0 writes the results
  } else {
    if (!mpi_world().root()) return 0;
    best = solve_event_design(s, ode, e, guess_of(starts[0]), "", false);
    if (best.refusal) return refuse_phases(flat, *best.refusal, diags);
  }
  if (!best.error.empty()) {  // no result: the summary says why (for each start)
    nlohmann::json extra;
    if (multi) {
      extra["design"]["multistart"] = multistart_json(*multi, settings);
      print_multistart(std::cerr, *multi, s.opt.criterion, settings);
    }
    write_error_summary(cli.output, info, best.error, extra);
    std::cerr << "morun: error: " << best.error << "\n";
    return 1;
  }
  runtime::OptimalControlProblem Pphys = e.Pphys;
  Pphys.collocation.n_e = static_cast<int>(best.result.optimization.element_times.size()) - 1;
  runtime::InputDesignProblem dphys;
  dphys.ocp = Pphys;
  dphys.parameters = e.J;
  dphys.measurements = e.m;
  dphys.criterion = e.crit;
  nlohmann::json extra = design_json(info, dphys, best.result);
  extra["status"] = best.status;
  extra["events"] = best.events;
  if (multi) {
    extra["design"]["multistart"] = multistart_json(*multi, settings);
    print_multistart(std::cerr, *multi, s.opt.criterion, settings);
  }
  write_optimization_outputs(cli.output, info, Pphys, best.result.optimization, extra);
  write_designed_input(cli.output, info, Pphys, best.result.optimization);
  if ((s.opt.plot || cli.plot) && best.result.optimization.trajectories.rows() > 0)
    plot_optimization(cli.output, info, Pphys, s.problem,
                      fmt::format("{}-optimal input design ({} phases)", s.opt.criterion,
                                  best.events.value("phases", std::size_t{0})));
  std::cerr << fmt::format("morun: {}-criterion information: {:.6g} (collocation), {:.6g} (re-simulated through "
                           "the events)\n",
                           s.opt.criterion, best.result.information_collocation, best.result.information_resimulated);
  std::cerr << fmt::format("morun: input design {}: objective {:.6g} after {} iterations\n", best.status,
                           best.result.optimization.objective, best.result.optimization.iterations);
  return best.status == "success" || best.status == "acceptable" ? 0 : 1;
}

}  // namespace mo::tools
