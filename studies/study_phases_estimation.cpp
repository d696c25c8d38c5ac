// Estimation on a model with events by multi-phase collocation; see study_phases.hpp.
//
// Every measurement time inside the horizon is a fixed cut between phases
// (continuity, no jump), so each sample is the value at the end of a phase
// (s = 1) and χ² is one Mayer term of the stacked model; only the phases next
// to a switch stretch with its time, which stays between its neighbouring
// sample times within one solve (a rebuild from the estimate moves it on).
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <iostream>

#include "mo/runtime/simulate.hpp"
#include "mo/symbolic/printer.hpp"
#include "mo/symbolic/traversal.hpp"
#include "study_events.hpp"
#include "study_internal.hpp"
#include "study_output.hpp"
#include "study_phases.hpp"
#include "study_phases_internal.hpp"

namespace mo::tools {

using namespace detail;

std::optional<PhaseLayout> sample_layout(const runtime::Model& model, const ModeSequence& seq,
                                         const std::vector<double>& samples, const runtime::Inputs& inputs,
                                         const std::vector<double>& p, double t0, double tf, double min_gap,
                                         std::string& why) {
  std::vector<double> cuts;
  for (double t : samples)
    if (t > t0 && t < tf && (cuts.empty() || t > cuts.back())) cuts.push_back(t);
  for (const auto& sw : seq.switches)
    for (double c : cuts)
      if (!sw.timed && std::abs(sw.time - c) < min_gap) {
        why = fmt::format("the guess switches at t = {:.9g}, on a sample time", sw.time);
        return std::nullopt;
      }
  // A sample on a time event is taken at the end of the phase before it
  // (the value the event's clauses read): the switch is its cut.
  std::erase_if(cuts, [&](double c) {
    return std::any_of(seq.switches.begin(), seq.switches.end(),
                       [&](const PhaseSwitch& sw) { return sw.timed && std::abs(sw.time - c) < min_gap; });
  });
  std::vector<double> grid{t0};
  grid.insert(grid.end(), cuts.begin(), cuts.end());
  grid.push_back(tf);
  runtime::SimulationOptions so;
  so.relative_tolerance = 1e-10;
  so.absolute_tolerance = 1e-10;
  const runtime::ModelInfo& info = model.info();
  if (info.num_base_states() < info.states.size())  // guesses of the sensitivity states, with their jumps
    so.sensitivities.method = runtime::SensitivityMethod::model_states;
  auto sim_model = model.clone();
  const auto sim = runtime::simulate(*sim_model, inputs, p, runtime::OutputGrid::at(grid), so);
  if (!sim.ok() || sim.trajectory.rows() != grid.size()) {
    why = sim.message;
    return std::nullopt;
  }
  const std::size_t nx = model.info().states.size();
  PhaseLayout out;
  out.mode.push_back(0);
  std::size_t next_switch = 0, mode = 0;
  for (std::size_t c = 0; c <= cuts.size(); ++c) {
    const double until = c < cuts.size() ? cuts[c] : tf;
    while (next_switch < seq.switches.size() && seq.switches[next_switch].time < until) {
      out.boundaries.push_back({seq.switches[next_switch].time, next_switch, seq.switches[next_switch].states_after});
      out.mode.push_back(++mode);
      ++next_switch;
    }
    if (c == cuts.size()) break;
    const auto row = sim.trajectory.row(c + 1);
    out.boundaries.push_back({cuts[c], std::nullopt, std::vector<double>(row.begin(), row.begin() + nx)});
    out.mode.push_back(mode);
  }
  return out;
}

std::vector<std::size_t> interleaving(const ModeSequence& seq, const std::vector<double>& samples, double t0) {
  std::vector<std::size_t> out;
  for (const auto& sw : seq.switches)
    out.push_back(static_cast<std::size_t>(
        std::count_if(samples.begin(), samples.end(), [&](double t) { return t > t0 && t < sw.time; })));
  return out;
}

std::map<std::size_t, double> stuck_switches(const std::vector<double>& switches, const std::vector<bool>& timed,
                                             const std::vector<double>& samples, double t0, double tf, double near) {
  std::vector<double> grid{t0};
  for (double t : samples)
    if (t > grid.back() && t < tf) grid.push_back(t);
  grid.push_back(tf);
  std::map<std::size_t, double> out;
  for (std::size_t k = 0; k < switches.size(); ++k)
    for (std::size_t c = 1; c + 1 < grid.size() && !(k < timed.size() && timed[k]); ++c) {
      if (std::abs(switches[k] - grid[c]) > near) continue;
      out[k] = switches[k] > grid[c] ? 0.5 * (grid[c - 1] + grid[c]) : 0.5 * (grid[c] + grid[c + 1]);
    }
  return out;
}

namespace {

/// A reason if a tick that moves with an estimated parameter lies on a
/// sample time: the sample is taken at the end of the phase before the tick,
/// which would move away from its time.
std::optional<std::string> moving_tick_on_sample(const symbolic::OdeModel& ode, const ModeSequence& seq,
                                                 const runtime::EstimationProblem& e,
                                                 const std::vector<double>& times, double min_gap) {
  for (const auto& sw : seq.switches) {
    if (!sw.timed || !sw.tick) continue;
    const symbolic::Expr roots[] = {ode.samples[sw.tick->first].start, ode.samples[sw.tick->first].interval};
    bool moving = false;
    for (symbolic::Expr leaf : symbolic::leaves(ode.arena, roots))
      for (const auto& fp : e.parameters) moving = moving || leaf == ode.parameters[fp.parameter].symbol;
    if (!moving) continue;
    for (double t : times)
      if (std::abs(t - sw.time) < min_gap)
        return fmt::format("the tick at t = {:.9g} moves with an estimated parameter and lies on a sample "
                           "time; sample between the ticks", sw.time);
  }
  return std::nullopt;
}

/// χ² = Σ ((y − m)/σ)² as an output of the stacked model: each sample is the
/// output at the end of the phase that ends at its time; a sample at t0 of a
/// state is its start value. Each m is a parameter of the stacked model
/// (valued 0 there, so that the generated code does not depend on the data;
/// its value goes to `measured_values`). Returns the output index or a reason.
std::optional<std::size_t> add_chi_square(PhasedModel& pm, const symbolic::OdeModel& base,
                                          const runtime::MeasurementTable& data, double t0,
                                          std::vector<std::pair<std::size_t, double>>& measured_values,
                                          std::string& why) {
  auto& a = pm.ode.arena;
  std::vector<double> ends;  // the end time of each phase
  for (const auto& b : pm.layout.boundaries) ends.push_back(fixed_end_time(pm, b));
  ends.push_back(data.times.back());
  symbolic::Expr sum = a.constant(0.0);
  for (std::size_t k = 0; k < data.times.size(); ++k)
    for (std::size_t r = 0; r < data.outputs.size(); ++r) {
      const double m = data.values(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(r));
      if (std::isnan(m)) continue;
      const std::size_t o = data.outputs[r];
      symbolic::Expr y;
      if (data.times[k] <= t0) {
        std::optional<std::size_t> state;
        for (std::size_t i = 0; i < base.states.size(); ++i)
          if (base.outputs[o].value == base.states[i].symbol) state = i;
        if (!state) {
          why = "a sample at the start time of '" + base.outputs[o].info.name + "', which is not a state";
          return std::nullopt;
        }
        y = pm.ode.states[pm.state(0, *state)].start;
      } else {
        const auto phase = phase_ending_at(ends, data.times[k]);
        if (phase == ends.end()) {
          why = fmt::format("no phase ends at the sample time {}", data.times[k]);
          return std::nullopt;
        }
        y = pm.ode.outputs[pm.output(static_cast<std::size_t>(phase - ends.begin()), o)].value;
      }
      symbolic::VariableInfo info;
      info.name = fmt::format("$sample{}.{}.measured", k + 1, base.outputs[o].info.name);
      const auto index = static_cast<std::int32_t>(pm.ode.parameters.size());
      const symbolic::Expr measured = a.symbol(info.name, symbolic::SymbolRole::Parameter, index);
      pm.ode.parameters.push_back({info, measured, 0.0});
      measured_values.emplace_back(static_cast<std::size_t>(index), m);
      const symbolic::Expr res = a.div(a.sub(y, measured), a.constant(data.sigma[r]));
      sum = a.add(sum, a.mul(res, res));
    }
  symbolic::OdeOutput out;
  out.info.name = "$phases.chi_square";
  out.value = sum;
  pm.ode.outputs.push_back(std::move(out));
  return pm.ode.outputs.size() - 1;
}

/// Fisher information, covariance and intervals at the estimate from the
/// sensitivities of the base model through its events (docs/events.md):
/// CVODES', or those of `with_states`, the model compiled with sensitivity
/// states for the free parameters, if given (held values, which CVODES does
/// not carry).
void statistics(const runtime::Model& model, const runtime::Model* with_states, const runtime::EstimationProblem& e,
                double t0, runtime::EstimationResult& r) {
  const auto& data = e.experiments.front().data;
  std::vector<std::size_t> J;
  for (const auto& fp : e.parameters) J.push_back(fp.parameter);
  runtime::SimulationOptions so;
  so.relative_tolerance = 1e-10;
  so.absolute_tolerance = 1e-10;
  so.sensitivities.method = runtime::SensitivityMethod::cvodes_analytic;
  so.sensitivities.parameters = J;
  std::vector<double> grid{t0};
  for (double t : data.times)
    if (t > grid.back()) grid.push_back(t);
  if (with_states) so.sensitivities.method = runtime::SensitivityMethod::model_states;
  auto sim_model = (with_states ? *with_states : model).clone();
  const auto sim = runtime::simulate(*sim_model, runtime::Inputs(), r.parameters, runtime::OutputGrid::at(grid), so);
  const auto n = static_cast<Eigen::Index>(J.size());
  r.fisher = Eigen::MatrixXd::Zero(n, n);
  if (!sim.ok() || sim.output_sensitivities.size() != grid.size()) {
    r.message += (r.message.empty() ? "" : "; ") + std::string("no statistics: the sensitivity simulation failed: ") + sim.message;
    return;
  }
  for (std::size_t k = 0; k < data.times.size(); ++k) {
    const auto row = static_cast<std::size_t>(std::find(grid.begin(), grid.end(), data.times[k]) - grid.begin());
    for (std::size_t c = 0; c < data.outputs.size(); ++c) {
      if (std::isnan(data.values(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(c)))) continue;
      const Eigen::RowVectorXd s = sim.output_sensitivities[row].row(static_cast<Eigen::Index>(data.outputs[c]));
      r.fisher += s.transpose() * s / (data.sigma[c] * data.sigma[c]);
    }
  }
  r.degrees_of_freedom = r.measurements - static_cast<int>(n);
  if (r.degrees_of_freedom <= 0) return;
  r.residual_variance = r.chi_square / r.degrees_of_freedom;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(r.fisher);
  if (!lu.isInvertible()) {
    r.warnings.push_back("the Fisher information is singular: the parameters are not identifiable from these data");
    return;
  }
  r.covariance = r.residual_variance * lu.inverse();
  r.t_quantile = runtime::student_t_quantile(0.5 + 0.5 * e.confidence, r.degrees_of_freedom);
  r.correlation = r.covariance;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double se = std::sqrt(std::max(0.0, r.covariance(i, i)));
    r.standard_error.push_back(se);
    r.confidence_interval.push_back({r.estimate[static_cast<std::size_t>(i)] - r.t_quantile * se,
                                     r.estimate[static_cast<std::size_t>(i)] + r.t_quantile * se});
    for (Eigen::Index j = 0; j < n; ++j)
      r.correlation(i, j) = r.covariance(i, j) / std::sqrt(r.covariance(i, i) * r.covariance(j, j));
  }
}

}  // namespace

PhasedEstimate phased_estimate(const runtime::Model& model, symbolic::OdeModel& ode, const RelationMap& rel,
                               const runtime::EstimationProblem& e, const StudyCli& cli,
                               const runtime::Model* with_states) {
  PhasedEstimate out;
  const runtime::ModelInfo& info = model.info();
  const auto& data = e.experiments.front().data;
  const double t0 = e.experiments.front().t0, tf = data.times.back();
  if (!(tf > t0)) throw UsageError("estimation needs samples after the start time");
  const double min_gap = 1e-6 * (tf - t0);
  std::vector<double> guess = e.parameter_values;
  for (const auto& fp : e.parameters)
    if (fp.initial_guess) guess[fp.parameter] = *fp.initial_guess;
  runtime::OptimalControlProblem Pphys;
  Pphys.t0 = t0;
  Pphys.tf = tf;
  runtime::OptimizationResult R;
  std::map<std::size_t, double> moved;  // switches to start on the other side of a sample time
  for (int attempt = 1; attempt <= kMaxAttempts; ++attempt) {
    ModeRecording rec = record_modes(model, ode, rel, runtime::Inputs(), guess, t0, tf, kMaxSwitches, min_gap);
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
    if (auto why = moving_tick_on_sample(ode, seq, e, data.times, min_gap)) {
      out.error = "estimation on a model with events: " + *why;
      return out;
    }
    std::string why;
    auto layout = sample_layout(model, seq, data.times, runtime::Inputs(), guess, t0, tf, min_gap, why);
    if (!layout) {
      out.error = "estimation on a model with events: " + why;
      return out;
    }
    PhasedModel pm = build_phased_model(ode, rel, seq, *layout, t0, tf, std::nullopt);
    std::vector<std::pair<std::size_t, double>> measured;
    const auto chi = add_chi_square(pm, ode, data, t0, measured, why);
    if (!chi) throw UsageError("estimation on a model with events: " + why);
    if (!cli.quiet)
      std::cerr << fmt::format("morun: events: {} modes ({}), {} phases cut at the sample times\n", seq.modes.size(),
                               describe_modes(ode, seq), pm.phases);
    BuiltModel built = build_model(pm.ode, cli.jobs, "morun", cli.run, cli.quiet);
    runtime::OptimalControlProblem P;
    P.t0 = t0;
    P.tf = tf;
    P.parameters = guess;
    for (auto fp : e.parameters) {
      fp.initial_guess = guess[fp.parameter];
      P.free_parameters.push_back(fp);
    }
    P.collocation = e.collocation;
    P.collocation.n_e = std::max(2, (e.collocation.n_e + static_cast<int>(pm.phases) - 1) / static_cast<int>(pm.phases));
    P.solver = e.solver;
    Guess g{guess, {}};
    runtime::OptimalControlProblem Q = phased_problem(P, pm, seq, g, info, min_gap);
    for (const auto& [index, value] : measured) Q.parameters[index] = value;
    Q.mayer.push_back({*chi, 1.0});
    runtime::OptimizationResult r;
    {
      PhaseScope phase(cli.run, "solve", fmt::format("estimation, {} phases", pm.phases));
      r = runtime::solve(*built.model, Q);
    }
    move_to_simulate(cli.run, r.timings.resimulation);
    const std::vector<double> taus = boundary_times(pm, r, t0, tf);
    const std::vector<double> switches = solved_switch_times(pm, r);
    R = physical_result(pm, r, taus, info, 0);
    Pphys.collocation.n_e = static_cast<int>(R.element_times.size()) - 1;
    EventCheck check = check_resimulation(const_cast<runtime::Model&>(model), ode, rel, seq, Pphys, R, switches, min_gap);
    const bool same = check.same_modes && check.modes &&
                      interleaving(*check.modes, data.times, t0) == interleaving(seq, data.times, t0);
    out.status = event_status(R, check, same, kTimeTolerance * (tf - t0), kStateTolerance);
    out.events = events_json(ode, seq, check, pm.phases, attempt, switches, same,
                             kTimeTolerance * (tf - t0), kStateTolerance);
    if (!cli.quiet) {
      std::cerr << fmt::format("morun: attempt {}: {}; re-simulated: {}, largest state difference {:.3g} of scale\n",
                               attempt, runtime::to_string(R.status),
                               check.modes ? describe_modes(ode, *check.modes) : check.failure, check.max_relative);
      if (!R.message.empty()) std::cerr << "morun: " << R.message << "\n";
    }
    if (R.parameters.size() != guess.size()) R.parameters = guess;  // nothing solved: report the guess
    if (out.status == "success" || out.status == "acceptable") {
      moved = stuck_switches(switches, pm.timed_switch, data.times, t0, tf, 10 * min_gap);
      if (!moved.empty()) {
        out.status = "switch_at_sample_time";
        if (!cli.quiet)
          std::cerr << "morun: a switching time ends on a sample time (its phase bound is active): solving again "
                       "with it on the other side\n";
      }
    }
    if ((out.status != "mode_sequence_changed" && out.status != "switch_at_sample_time") || attempt == kMaxAttempts)
      break;
    guess = R.parameters;
  }
  runtime::EstimationResult& er = out.result;
  er.status = R.status;
  er.message = R.message;
  for (const auto& fp : e.parameters) {
    er.names.push_back(info.parameters[fp.parameter].name);
    er.estimate.push_back(R.parameters[fp.parameter]);
  }
  er.parameters = R.parameters;
  er.chi_square = R.objective;
  er.iterations = R.iterations;
  for (Eigen::Index k = 0; k < data.values.size(); ++k)
    if (!std::isnan(data.values.data()[k])) ++er.measurements;
  statistics(model, with_states, e, t0, er);
  if (out.status != "success" && out.status != "acceptable" && er.status == runtime::OptimizationStatus::success)
    er.status = runtime::OptimizationStatus::invalid_problem;  // the events check failed: not an estimate to use
  er.experiments.push_back(R);
  return out;
}

int estimation_with_events(frontend::flat::Model& flat, const StudyCli& cli, StudyOptions opt, ProblemOutputs problem,
                           symbolic::OdeModel& ode, frontend::DiagnosticEngine& diags, const Relower& relower) {
  const RelationMap rel = match_relations(ode);
  if (auto r = check_event_constructs(ode, rel)) return refuse_phases(flat, *r, diags);
  Study s{flat, cli, std::move(opt), std::move(problem), build_model(ode, cli.jobs, "morun", cli.run, cli.quiet)};
  const runtime::ModelInfo& info = s.info();
  if (!info.inputs.empty() || s.opt.data.size() != 1)
    throw UsageError("estimation on a model with events takes one experiment (one data file) on a model "
                     "without inputs (docs/events.md)");
  runtime::EstimationProblem e;
  e.parameters = free_parameters(s);
  if (e.parameters.empty()) throw UsageError("estimation needs parameters declared free = true in the study");
  runtime::EstimationExperiment ex;
  ex.t0 = s.problem.t0;
  ex.data = read_measurements(resolve_path(cli.study_file, s.opt.data[0]), info, s.opt);
  e.experiments.push_back(std::move(ex));
  e.parameter_values = parameter_values(info, cli);
  e.collocation = collocation_options(s.opt);
  e.solver = solver_options(s);
  e.confidence = s.opt.confidence;
  // CVODES does not carry sensitivities through held values: the statistics
  // then come from the model compiled with sensitivity states.
  BuiltModel with_states;
  if (rel.holds_values()) {
    std::vector<std::string> names;
    for (const auto& fp : e.parameters) names.push_back(info.parameters[fp.parameter].name);
    symbolic::OdeModel sens = relower(names);
    with_states = build_model(sens, cli.jobs, "morun", cli.run, cli.quiet);
  }
  PhasedEstimate pe = phased_estimate(*s.built.model, ode, rel, e, cli, with_states.model.get());
  if (pe.refusal) return refuse_phases(flat, *pe.refusal, diags);
  if (!pe.error.empty()) {
    std::cerr << "morun: error: " << pe.error << "\n";
    return 1;
  }
  runtime::EstimationResult& er = pe.result;
  er.status = er.experiments.front().status;  // Ipopt's; `status` in summary.json says whether the check held
  {
    PhaseScope phase(cli.run, "simulate", "fit at the estimate");
    write_estimation_outputs(cli.output, *s.built.model, e, er);
  }
  const std::string path = cli.output + "/summary.json";
  nlohmann::json j;
  {
    std::ifstream in(path);
    j = nlohmann::json::parse(in);
  }
  j["status"] = pe.status;
  j["events"] = pe.events;
  runtime::write_file_atomic(path, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
  print_estimates(std::cerr, er);
  std::cerr << fmt::format("morun: estimation {}\n", pe.status);
  return pe.status == "success" || pe.status == "acceptable" ? 0 : 1;
}

int monte_carlo_with_events(frontend::flat::Model& flat, const StudyCli& cli, StudyOptions opt,
                            ProblemOutputs problem, symbolic::OdeModel& ode, frontend::DiagnosticEngine& diags) {
  const RelationMap rel = match_relations(ode);
  if (auto r = check_event_constructs(ode, rel)) return refuse_phases(flat, *r, diags);
  Study s{flat, cli, std::move(opt), std::move(problem), build_model(ode, cli.jobs, "morun", cli.run, cli.quiet)};
  if (!s.info().inputs.empty())
    throw UsageError("monte_carlo on a model with events takes a model without inputs (docs/events.md)");
  // The model has sensitivity states for the free parameters: with held
  // values (which CVODES does not carry) the statistics take those.
  const bool held = rel.holds_values();
  StudyCli quiet = cli;
  quiet.quiet = true;
  quiet.run = nullptr;
  quiet.jobs = 1;
  s.estimate = [&](const runtime::EstimationProblem& e) {
    PhasedEstimate pe = phased_estimate(*s.built.model, ode, rel, e, quiet, held ? s.built.model.get() : nullptr);
    if (pe.refusal || !pe.error.empty()) {
      runtime::EstimationResult failed;
      failed.status = runtime::OptimizationStatus::invalid_problem;
      failed.message = pe.refusal ? pe.refusal->message : pe.error;
      return failed;
    }
    return std::move(pe.result);
  };
  return monte_carlo(s);
}

}  // namespace mo::tools
