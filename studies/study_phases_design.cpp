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
  for (const auto& b : pm.layout.boundaries) ends.push_back(b.switch_index ? -1.0 : b.time);
  ends.push_back(m.times.empty() ? t0 : std::max(m.times.back(), ends.empty() ? t0 : ends.back()));
  runtime::MeasurementDesign out;
  out.times = {1.0};
  for (std::size_t k = 0; k < m.times.size(); ++k) {
    const auto phase = std::find(ends.begin(), ends.end(), m.times[k]);
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

/// What one multi-phase design solve gives, on physical time.
struct PhasedDesign {
  runtime::InputDesignResult result;  ///< optimization on physical time, F of the collocation and re-simulated
  EventCheck check;
  ModeSequence seq;
  std::vector<double> switches;
  std::size_t phases = 0;
};

}  // namespace

int design_with_events(frontend::flat::Model& flat, const StudyCli& cli, StudyOptions opt, ProblemOutputs problem,
                       symbolic::OdeModel& ode, frontend::DiagnosticEngine& diags) {
  if (problem.free_final_time)
    throw UsageError("a free finalTime on a model with events is not supported (docs/events.md)");
  const RelationMap rel = match_relations(ode);
  if (auto r = check_event_constructs(ode, rel)) return refuse_phases(flat, *r, diags);
  Study s{flat, cli, std::move(opt), std::move(problem), build_model(ode, cli.jobs, "morun", cli.run, cli.quiet)};
  const runtime::ModelInfo& info = s.info();
  if (!s.opt.starts.empty() || s.opt.random_starts > 0)
    throw UsageError("design on a model with events takes one start (no study option starts)");
  const runtime::OptimalControlProblem P = base_problem(s);
  std::vector<std::size_t> J;
  for (const auto& name : s.opt.parameters) J.push_back(parameter_index(info, name));
  const runtime::MeasurementDesign m = measurements(s, P.t0, P.tf);
  const runtime::DesignCriterion crit = criterion_of(s.opt.criterion);
  const double min_gap = 1e-6 * (P.tf - P.t0), time_tol = kTimeTolerance * (P.tf - P.t0);
  std::optional<std::size_t> lagrange;
  if (!P.lagrange.empty()) lagrange = P.lagrange.front().output;
  Guess guess = initial_guess(P);
  runtime::OptimalControlProblem Pphys = P;
  for (auto& c : Pphys.controls) c.blocking_factors.clear();
  runtime::InputDesignResult result;
  std::string status;
  nlohmann::json events;
  std::map<std::size_t, double> moved;
  for (int attempt = 1; attempt <= kMaxAttempts; ++attempt) {
    const runtime::Inputs inputs = guess_inputs(guess, P, info.inputs.size());
    ModeRecording rec = record_modes(*s.built.model, ode, rel, inputs, guess.parameters, P.t0, P.tf, kMaxSwitches, min_gap);
    if (rec.refusal) return refuse_phases(flat, *rec.refusal, diags);
    if (!rec.sequence) {
      std::cerr << "morun: error: the simulation of the guess failed: " << rec.simulation_failure << "\n";
      return 1;
    }
    ModeSequence seq = *rec.sequence;
    for (const auto& [k, t] : moved)
      if (k < seq.switches.size()) seq.switches[k].time = t;
    moved.clear();
    std::string why;
    auto layout = sample_layout(*s.built.model, seq, m.times, inputs, guess.parameters, P.t0, P.tf, min_gap, why);
    if (!layout) {
      std::cerr << "morun: error: design on a model with events: " << why << "\n";
      return 1;
    }
    PhasedModel pm = build_phased_model(ode, rel, seq, *layout, P.t0, P.tf, lagrange);
    runtime::InputDesignProblem d;
    d.parameters = J;
    d.criterion = crit;
    d.measurements = add_samples(pm, ode, m, J, P.t0);
    std::cerr << fmt::format("morun: events: {} modes ({}), {} phases cut at the measurement times\n",
                             seq.modes.size(), describe_modes(ode, seq), pm.phases);
    BuiltModel built = build_model(pm.ode, cli.jobs, "morun", cli.run, cli.quiet);
    runtime::OptimalControlProblem Pk = P;
    Pk.collocation.n_e = std::max(2, (P.collocation.n_e + static_cast<int>(pm.phases) - 1) / static_cast<int>(pm.phases));
    d.ocp = phased_problem(Pk, pm, seq, guess, info, min_gap, true);
    runtime::InputDesignResult r;
    {
      PhaseScope phase(cli.run, "solve", fmt::format("input design, {} phases", pm.phases));
      r = runtime::design_input(*built.model, d);
    }
    move_to_simulate(cli.run, r.optimization.timings.resimulation);
    const std::vector<double> taus = boundary_times(pm, r.optimization, P.t0, P.tf);
    const std::vector<double> switches = solved_switch_times(pm, r.optimization);
    result.optimization = physical_result(pm, r.optimization, taus, info, P.controls.size());
    runtime::OptimizationResult& R = result.optimization;
    Pphys.collocation.n_e = static_cast<int>(R.element_times.size()) - 1;
    EventCheck check = check_resimulation(*s.built.model, ode, rel, seq, Pphys, R, switches, min_gap);
    const bool same = check.same_modes && check.modes &&
                      interleaving(*check.modes, m.times, P.t0) == interleaving(seq, m.times, P.t0);
    status = event_status(R, check, same, time_tol, kStateTolerance);
    events = events_json(ode, seq, check, pm.phases, attempt, switches, same, time_tol, kStateTolerance);
    result.fisher_collocation = r.fisher_collocation;
    result.information_collocation = r.information_collocation;
    result.information_resimulated = std::nan("");
    result.fisher_resimulated.resize(0, 0);
    if (R.parameters.size() == info.parameters.size() && check.modes) {  // check.modes: the phases ascend
      try {
        result.fisher_resimulated = runtime::fisher_information(
            *s.built.model, runtime::optimal_inputs(Pphys, R, info.inputs.size()), R.parameters, P.t0, m, J);
        result.information_resimulated = runtime::criterion_information(crit, result.fisher_resimulated);
      } catch (const std::runtime_error& e) {
        R.check.message += std::string(" (Fisher replay: ") + e.what() + ")";
      }
    }
    std::cerr << fmt::format("morun: attempt {}: {}; re-simulated: {}, largest state difference {:.3g} of scale\n",
                             attempt, runtime::to_string(R.status),
                             check.modes ? describe_modes(ode, *check.modes) : check.failure, check.max_relative);
    if (!R.message.empty()) std::cerr << "morun: " << R.message << "\n";
    if (status == "success" || status == "acceptable") {
      moved = stuck_switches(switches, m.times, P.t0, P.tf, 10 * min_gap);
      if (!moved.empty()) status = "switch_at_sample_time";
    }
    if ((status != "mode_sequence_changed" && status != "switch_at_sample_time") || attempt == kMaxAttempts) break;
    if (R.parameters.size() == info.parameters.size()) guess.parameters = R.parameters;
    for (std::size_t c = 0; c < P.controls.size() && check.modes; ++c) {
      std::vector<double> starts(R.element_times.begin(), R.element_times.end() - 1);
      guess.controls[c] = runtime::piecewise_constant_input(starts, R.control_values[c]);
    }
  }
  runtime::InputDesignProblem dphys;
  dphys.ocp = Pphys;
  dphys.parameters = J;
  dphys.measurements = m;
  dphys.criterion = crit;
  nlohmann::json extra = design_json(info, dphys, result);
  extra["status"] = status;
  extra["events"] = events;
  write_optimization_outputs(cli.output, info, Pphys, result.optimization, extra);
  write_designed_input(cli.output, info, Pphys, result.optimization);
  if (s.opt.plot || cli.plot)
    plot_optimization(cli.output, info, Pphys, s.problem,
                      fmt::format("{}-optimal input design ({} phases)", s.opt.criterion,
                                  events["phases"].get<std::size_t>()));
  std::cerr << fmt::format("morun: {}-criterion information: {:.6g} (collocation), {:.6g} (re-simulated through "
                           "the events)\n",
                           s.opt.criterion, result.information_collocation, result.information_resimulated);
  std::cerr << fmt::format("morun: input design {}: objective {:.6g} after {} iterations\n", status,
                           result.optimization.objective, result.optimization.iterations);
  return status == "success" || status == "acceptable" ? 0 : 1;
}

}  // namespace mo::tools
