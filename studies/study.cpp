// The study runner; see study.hpp.
#include "study.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <iostream>

#include "measured_outputs.hpp"
#include "mpi_world.hpp"
#include "multistart.hpp"
#include "pipeline.hpp"
#include "study_events.hpp"
#include "study_internal.hpp"
#include "study_output.hpp"
#include "study_phases.hpp"
#include "study_time_scaling.hpp"
#include "study_plots.hpp"

namespace fs = std::filesystem;

namespace mo::tools {

namespace detail {

namespace flat = frontend::flat;

namespace {

std::optional<double> attribute(const flat::Model& m, const std::string& name,
                                frontend::ast::ExprPtr flat::Attributes::*which) {
  const std::int32_t v = m.find(name);
  if (v < 0) return std::nullopt;
  const auto& expr = m.variables[static_cast<std::size_t>(v)].attr.*which;
  return expr ? constant_value(m, *expr) : std::nullopt;
}

runtime::Bounds bounds_of(const flat::Model& m, const std::string& name) {
  runtime::Bounds b;
  b.lo = attribute(m, name, &flat::Attributes::min).value_or(b.lo);
  b.hi = attribute(m, name, &flat::Attributes::max).value_or(b.hi);
  return b;
}

}  // namespace

std::size_t output_index(const runtime::ModelInfo& info, const std::string& name) {
  if (auto k = info.output_index(name)) return *k;
  std::string known;
  for (const auto& y : info.outputs)
    if (!y.name.starts_with("$") && !y.name.starts_with("d("))
      known += (known.empty() ? "" : ", ") + y.name;
  throw UsageError("'" + name + "' is not a variable of the model (outputs: " + known + ")");
}

std::size_t parameter_index(const runtime::ModelInfo& info, const std::string& name) {
  if (auto k = info.parameter_index(name)) return *k;
  throw UsageError("'" + name + "' is not a parameter of the model");
}

/// The model's defaults with --set p=v applied.
std::vector<double> parameter_values(const runtime::ModelInfo& info, const StudyCli& cli) {
  std::vector<double> p = info.default_parameters();
  for (const auto& text : cli.sets) {
    auto [name, value] = split_assignment(text, "--set");
    p[parameter_index(info, name)] = number(value, "--set " + text);
  }
  return p;
}

void move_to_simulate(RunContext* run, double seconds) {
  if (!run) return;
  run->timings.add("solve", -seconds);
  run->timings.add("simulate", seconds);
}

runtime::ProgressCallback solver_progress(RunContext* run) {
  if (!run || !run->progress) return nullptr;
  Progress* progress = run->progress;
  return [progress](const runtime::IterationInfo& it) {
    progress->detail(fmt::format("iteration {}{}, objective {:.6g}, infeasibility {:.2e}", it.iteration,
                                 it.restoration ? " (restoration)" : "", it.objective, it.inf_pr));
    return true;
  };
}

runtime::SolverOptions solver_options(const Study& s) {
  runtime::SolverOptions so;
  const StudyOptions& o = s.opt;
  so.hessian = o.hessian == "exact"            ? runtime::HessianMode::exact
               : o.hessian == "limited_memory" ? runtime::HessianMode::limited_memory
                                               : runtime::HessianMode::automatic;
  so.tolerance = o.tol;
  so.max_iterations = o.max_iter;
  so.max_cpu_seconds = o.max_cpu_time;
  so.acceptable_tolerance = o.acceptable_tol;
  so.acceptable_iterations = o.acceptable_iter;
  so.acceptable_objective_change = o.acceptable_obj_change_tol;
  so.log_file = (fs::path(s.cli.output) / "ipopt.log").string();
  so.progress = solver_progress(s.cli.run);
  for (const auto& text : o.ipopt_options) {
    auto [name, value] = split_assignment(text, "study option ipopt_options:");
    so.ipopt_options[name] = value;
  }
  return so;
}

runtime::CollocationOptions collocation_options(const StudyOptions& o) {
  runtime::CollocationOptions c;
  c.n_e = o.n_e;
  c.n_cp = o.n_cp;
  c.scheme = o.scheme == "gauss" ? runtime::CollocationScheme::gauss : runtime::CollocationScheme::radau;
  c.element_lengths = o.element_lengths;
  c.init_traj = o.init_traj;
  c.nominal_traj = o.nominal_traj && o.init_traj;
  return c;
}

/// Free parameters: `free = true` in the study, with min/max and initialGuess.
std::vector<runtime::FreeParameter> free_parameters(const Study& s) {
  std::vector<runtime::FreeParameter> out;
  for (const flat::Variable& v : s.flat.variables) {
    if (v.variability != frontend::ast::Variability::Parameter || !v.attr.free) continue;
    if (constant_value(s.flat, *v.attr.free).value_or(0.0) == 0.0) continue;
    runtime::FreeParameter fp;
    fp.parameter = parameter_index(s.info(), v.name);
    fp.bounds = bounds_of(s.flat, v.name);
    fp.initial_guess = attribute(s.flat, v.name, &flat::Attributes::initial_guess);
    out.push_back(fp);
  }
  return out;
}

/// The inputs that study option `inputs` gives signals (optimal_control and
/// design: one entry); the model's own iteration variables cannot be given.
std::map<std::size_t, std::shared_ptr<const runtime::InputSignal>> given_control_inputs(
    const Study& s, const std::vector<const symbolic::LoopInput*>& loop) {
  if (s.opt.inputs.empty()) return {};
  if (s.opt.inputs.size() > 1)
    throw UsageError(fmt::format("study option inputs: {} has one experiment, so one entry \"u=SPEC;v=SPEC\" "
                                 "(given {})",
                                 s.opt.task, s.opt.inputs.size()));
  auto given = given_inputs(s.info(), s.opt.inputs[0], s.cli.study_file);
  for (const auto& [input, signal] : given)
    if (loop[input])
      throw UsageError("study option inputs: '" + s.info().inputs[input].name +
                       "' is an iteration variable of the model's nonlinear blocks, not an input");
  return given;
}

/// The Optimica problem: every input a control (bounds, initialGuess) unless
/// study option `inputs` gives it a signal, free parameters, objective terms
/// and constraints through their outputs.
runtime::OptimalControlProblem base_problem(const Study& s) {
  const runtime::ModelInfo& info = s.info();
  runtime::OptimalControlProblem p;
  p.t0 = s.problem.t0;
  p.tf = s.problem.tf;
  std::vector<const symbolic::LoopInput*> loop(info.inputs.size(), nullptr);
  for (const symbolic::LoopInput& li : s.loops.inputs) loop[li.input] = &li;
  p.fixed_inputs = given_control_inputs(s, loop);
  for (std::size_t i = 0; i < info.inputs.size(); ++i) {
    if (p.fixed_inputs.contains(i)) continue;
    runtime::FreeControl c;
    c.input = i;
    if (const symbolic::LoopInput* li = loop[i]) {  // an iteration variable: free at every point
      c.per_point = true;
      c.bounds = {li->min, li->max};
      c.initial_guess = runtime::constant_input(std::clamp(li->start, li->min, li->max));
      p.controls.push_back(std::move(c));
      continue;
    }
    c.bounds = bounds_of(s.flat, info.inputs[i].name);
    if (auto g = attribute(s.flat, info.inputs[i].name, &flat::Attributes::initial_guess))
      c.initial_guess = runtime::constant_input(*g);
    c.blocking_factors = s.opt.blocking_factors;
    p.controls.push_back(std::move(c));
  }
  p.free_parameters = free_parameters(s);
  p.parameters = parameter_values(info, s.cli);
  if (s.problem.mayer) p.mayer.push_back({output_index(info, *s.problem.mayer), 1.0});
  if (s.problem.lagrange) p.lagrange.push_back({output_index(info, *s.problem.lagrange), 1.0});
  for (std::size_t k : s.loops.residuals) p.path_constraints.push_back({k, runtime::Bounds{0.0, 0.0}});
  for (const ProblemConstraint& c : s.problem.constraints) {
    const runtime::Bounds b{c.lo, c.hi};
    if (c.time)
      p.point_constraints.push_back({output_index(info, c.output), *c.time, b});
    else
      p.path_constraints.push_back({output_index(info, c.output), b});
  }
  p.collocation = collocation_options(s.opt);
  p.solver = solver_options(s);
  apply_control_options(s, p);
  guess_iteration_variables(s, p);
  apply_init_result(s, p);
  return p;
}

namespace {

int report(const std::string& task, const runtime::OptimizationResult& r) {
  std::cerr << fmt::format("morun: {} {}: objective {:.6g} after {} iterations ({:.2f} s)\n", task,
                           runtime::to_string(r.status), r.objective, r.iterations,
                           r.timings.solve);
  if (!r.message.empty()) std::cerr << "morun: " << r.message << "\n";
  for (const auto& retry : r.retries) std::cerr << "morun: retried: " << retry << "\n";
  if (r.check.performed && !r.check.worst_state.empty())
    std::cerr << fmt::format(
        "morun: re-simulated: largest state difference {:.3g} ({} at t = {:.3g}), largest bound "
        "violation {:.3g}{}\n",
        r.check.max_state_difference, r.check.worst_state, r.check.worst_state_time,
        r.check.max_bound_violation,
        r.check.max_bound_violation > 0 ? " (" + r.check.worst_bound + ")" : "");
  return r.ok() ? 0 : 1;
}

int optimal_control(Study& s) {
  runtime::OptimalControlProblem p = base_problem(s);
  const auto& free = s.problem.free_final_time;
  std::optional<std::size_t> tf_index;
  if (free) {
    tf_index = parameter_index(s.info(), free->parameter);
    bound_final_time(p, *tf_index, free->start);
  }
  runtime::OptimizationResult r;
  {
    PhaseScope phase(s.cli.run, "solve", "optimal control");
    r = runtime::solve(*s.built.model, p);
  }
  move_to_simulate(s.cli.run, r.timings.resimulation);
  nlohmann::json extra = nlohmann::json::object();
  if (free) {  // report in real time: [t0, tf] instead of τ ∈ [0, 1]
    const double tf = r.parameters.empty() ? std::nan("") : r.parameters[*tf_index];
    rescale_result(r, free->start, tf);
    p.t0 = free->start;
    p.tf = tf;
    extra["final_time"] = tf;
    std::cerr << fmt::format("morun: free final time: {:.6g}\n", tf);
  }
  write_optimization_outputs(s.cli.output, s.info(), p, r, extra);
  // A problem refused before the solve has no trajectory: nothing to plot, and the reason follows.
  if ((s.opt.plot || s.cli.plot) && r.trajectories.rows() > 0)
    plot_optimization(s.cli.output, s.info(), p, s.problem, "optimal control");
  return report("optimal control", r);
}

}  // namespace

namespace {

runtime::DesignCriterion criterion(const std::string& c) {
  if (c == "A") return runtime::DesignCriterion::A;
  if (c == "D") return runtime::DesignCriterion::D;
  if (c == "E") return runtime::DesignCriterion::E;
  return runtime::DesignCriterion::T;
}

}  // namespace

runtime::MeasurementDesign measurements(const Study& s, double t0, double tf) {
  runtime::MeasurementDesign m;
  for (const auto& name : s.opt.outputs) m.outputs.push_back(output_index(s.info(), name));
  if (m.outputs.empty()) throw UsageError("study option 'outputs' names no measured output");
  m.sigma = s.opt.sigma;
  if (m.sigma.size() == 1) m.sigma.assign(m.outputs.size(), m.sigma[0]);
  if (m.sigma.size() != m.outputs.size())
    throw UsageError(fmt::format("study option 'sigma' has {} values for {} outputs",
                                 m.sigma.size(), m.outputs.size()));
  m.times = s.opt.measurement_times.empty()
                ? runtime::MeasurementDesign::uniform_times(
                      t0, tf, static_cast<std::size_t>(s.opt.measurements))
                : s.opt.measurement_times;
  return m;
}

namespace {

int design(Study& s) {
  runtime::InputDesignProblem d;
  d.ocp = base_problem(s);
  for (const auto& name : s.opt.parameters) d.parameters.push_back(parameter_index(s.info(), name));
  d.measurements = measurements(s, d.ocp.t0, d.ocp.tf);
  d.criterion = criterion(s.opt.criterion);
  d.hessian_fallback = s.opt.hessian_fallback;
  const std::vector<DesignStart> starts = design_starts(s.opt, d.ocp, s.info());
  const MultistartSettings settings{s.cli.jobs, s.cli.output, s.opt.cluster_tol, s.cli.run};
  std::optional<MultistartResult> multi;
  runtime::InputDesignResult r;
  {
    PhaseScope phase(s.cli.run, "solve", "input design");
    if (starts.size() > 1) {
      multi = run_multistart(*s.built.model, d, starts, settings);
      if (!multi) return 0;  // an MPI rank other than 0: rank 0 writes the results
      r = std::move(multi->best);
    } else {
      if (!mpi_world().root()) return 0;  // one start: rank 0 solves it
      for (std::size_t c = 0; c < d.ocp.controls.size(); ++c)
        if (starts[0].guesses[c]) d.ocp.controls[c].initial_guess = starts[0].guesses[c];
      r = runtime::design_input(*s.built.model, d);
      r.start_information = {r.optimization.ok() ? r.information_collocation : std::nan("")};
    }
  }
  move_to_simulate(s.cli.run, r.optimization.timings.resimulation);
  nlohmann::json extra = design_json(s.info(), d, r);
  if (multi) {
    extra["design"]["multistart"] = multistart_json(*multi, settings);
    print_multistart(std::cerr, *multi, s.opt.criterion, settings);
  }
  write_optimization_outputs(s.cli.output, s.info(), d.ocp, r.optimization, extra);
  write_designed_input(s.cli.output, s.info(), d.ocp, r.optimization);
  if ((s.opt.plot || s.cli.plot) && r.optimization.trajectories.rows() > 0) {
    plot_optimization(s.cli.output, s.info(), d.ocp, s.problem,
                      fmt::format("{}-optimal input design (n_e = {}, n_cp = {})", s.opt.criterion,
                                  d.ocp.collocation.n_e, d.ocp.collocation.n_cp));
    bool written = false;
    {
      PhaseScope phase(s.cli.run, "simulate", "sensitivities under the designed input");
      written = write_design_sensitivities(s.cli.output, *s.built.model, d, r.optimization);
    }
    if (written) plot_design_sensitivities(s.cli.output, s.info(), d);
  }
  std::cerr << fmt::format("morun: {}-criterion information: {:.6g} (collocation), {:.6g} "
                           "(re-simulated)\n",
                           s.opt.criterion, r.information_collocation, r.information_resimulated);
  return report("input design", r.optimization);
}

int estimation(Study& s) {
  runtime::EstimationProblem e;
  e.parameters = free_parameters(s);
  if (e.parameters.empty())
    throw UsageError("estimation needs parameters declared free = true in the study");
  if (s.opt.data.empty()) throw UsageError("estimation needs study option 'data' (CSV files)");
  for (std::size_t k = 0; k < s.opt.data.size(); ++k) {
    runtime::EstimationExperiment ex;
    ex.t0 = s.problem.t0;
    ex.data = read_measurements(resolve_path(s.cli.study_file, s.opt.data[k]), s.info(), s.opt);
    const std::string spec = k < s.opt.inputs.size() ? s.opt.inputs[k] : "";
    ex.inputs = experiment_inputs(s.info(), spec, s.cli.study_file);
    e.experiments.push_back(std::move(ex));
  }
  e.parameter_values = parameter_values(s.info(), s.cli);
  e.collocation = collocation_options(s.opt);
  e.solver = solver_options(s);
  e.confidence = s.opt.confidence;
  runtime::EstimationResult r;
  {
    PhaseScope phase(s.cli.run, "solve", "estimation");
    r = runtime::estimate_parameters(*s.built.model, e);
  }
  for (const auto& ex : r.experiments) move_to_simulate(s.cli.run, ex.timings.resimulation);
  {
    PhaseScope phase(s.cli.run, "simulate", "fit at the estimate");
    write_estimation_outputs(s.cli.output, *s.built.model, e, r);
  }
  if (s.opt.plot || s.cli.plot) {
    {
      PhaseScope phase(s.cli.run, "simulate", "prediction band at the estimate");
      write_prediction(s.cli.output, *s.built.model, e, r);
    }
    plot_fit(s.cli.output, s.info(), e, r);
  }
  print_estimates(std::cerr, r);
  return r.status == runtime::OptimizationStatus::success ||
                 r.status == runtime::OptimizationStatus::acceptable
             ? 0
             : 1;
}

/// The parameters that need sensitivity states: a design's parameters of
/// interest, or the free parameters of a Monte-Carlo check (for its
/// Cramér–Rao bounds). Empty for the other tasks.
std::vector<std::string> sensitivity_parameters(const flat::Model& flat, const StudyOptions& o) {
  if (o.task == "design") {
    if (o.parameters.empty())
      throw UsageError("design needs study option 'parameters' (the parameters of interest)");
    return o.parameters;
  }
  std::vector<std::string> out;
  if (o.task == "monte_carlo")
    for (const auto& v : flat.variables)
      if (v.variability == frontend::ast::Variability::Parameter && v.attr.free &&
          constant_value(flat, *v.attr.free).value_or(0) != 0)
        out.push_back(v.name);
  if (o.task == "monte_carlo" && out.empty())
    throw UsageError("monte_carlo needs parameters declared free = true in the study");
  return out;
}

/// The variables a task measures: `outputs`, and for an estimation the
/// columns of its data files (any variable of the model may be measured).
std::vector<std::string> measured_names(const StudyOptions& o, const std::string& study_file) {
  std::vector<std::string> names = o.outputs;
  if (o.task == "estimation")
    for (const auto& file : o.data)
      for (auto& column : csv_columns(resolve_path(study_file, file))) names.push_back(std::move(column));
  return names;
}

/// The inputs that study option `inputs` names ("u=SPEC;v=SPEC" entries).
std::vector<std::string> given_input_names(const StudyOptions& o) {
  std::vector<std::string> names;
  for (const std::string& entry : o.inputs)
    for (std::size_t begin = 0; begin <= entry.size();) {
      const std::size_t end = std::min(entry.find(';', begin), entry.size());
      const std::string item = entry.substr(begin, end - begin);
      if (const auto eq = item.find('='); eq != std::string::npos) names.push_back(item.substr(0, eq));
      begin = end + 1;
    }
  return names;
}

/// In optimal_control and design every input not given a signal is a free
/// control: one that the initial system reads would make x0 depend on the
/// control at t0, which the collocation has no derivative for. Reported at
/// the input's declaration.
bool refuse_controls_in_initial_system(const flat::Model& flat, const symbolic::OdeModel& ode,
                                       const std::vector<std::string>& given, frontend::DiagnosticEngine& diags) {
  const std::vector<bool> read = ode.inputs_in_initial_system();
  bool refused = false;
  for (std::size_t k = 0; k < read.size(); ++k) {
    if (!read[k]) continue;
    const std::string& name = ode.inputs[k].info.name;
    if (std::find(given.begin(), given.end(), name) != given.end()) continue;
    const std::int32_t var = flat.find(name);
    const frontend::SourceRange where = var >= 0 ? flat.variables[std::size_t(var)].range
                                        : flat.optimization                ? flat.optimization->range
                                                                           : frontend::SourceRange{};
    // Printed alone: the lowering's warnings are on stderr already.
    std::cerr << diags.format(diags.report(
        frontend::DiagId::BadOptimization, where,
        "the initial system reads input '" + name + "' (the start values depend on its value at the start "
        "time), so it cannot be a free control of this study; initialise without it, give it a signal "
        "(study option inputs), or make it a parameter"));
    refused = true;
  }
  return refused;
}

}  // namespace

}  // namespace detail

using namespace detail;

int run_study(flat::Model& flat, const StudyCli& cli, frontend::DiagnosticEngine& diags) {
  const MpiWorld& world = mpi_world();
  if (!world.root()) send_output_to_log(cli.output, world.rank);
  std::vector<OptionOverride> overrides;
  for (const auto& text : cli.overrides_text) {
    auto [name, value] = split_assignment(text, "--option");
    overrides.push_back({name, value});
  }
  ParsedOptions parsed = parse_study_options(*flat.optimization, overrides, diags);
  auto problem = add_problem_outputs(flat, diags);
  for (const auto& e : parsed.errors) std::cerr << "morun: error: " << e << "\n";
  const bool constrained = parsed.options.task == "optimal_control" || parsed.options.task == "design";
  if (problem && constrained) add_bound_constraints(flat, *problem);
  if (problem && problem->free_final_time) {
    if (parsed.options.task != "optimal_control")
      throw UsageError("a free finalTime is supported by task optimal_control only (this study's "
                       "task is " + parsed.options.task + ")");
    scale_time(flat, *problem);
  }
  std::optional<symbolic::OdeModel> ode;
  bool phased = false;  // a model with events: multi-phase collocation for every task
  {
    PhaseScope phase(cli.run, "lower", flat.name);
    if (parsed.errors.empty() && parsed.ok && problem) ode = lower_model(flat, diags);
    phased = ode && has_events(*ode);
    diags.print(std::cerr);  // once: warnings, or the errors that stop here
    if (!parsed.errors.empty()) return 2;
    if (!ode) return 1;
    std::vector<std::string> states;
    for (const auto& x : ode->states) states.push_back(x.info.name);
    drop_state_bounds(*problem, states);
    add_measured_outputs(*ode, measured_names(parsed.options, cli.study_file));
    if (const auto params = sensitivity_parameters(flat, parsed.options); !params.empty())
      if (auto error = add_named_sensitivities(*ode, params); !error.empty()) throw UsageError(error);
  }
  if (constrained && refuse_controls_in_initial_system(flat, *ode, given_input_names(parsed.options), diags))
    return 1;
  if (phased) {
    fs::create_directories(cli.output);
    const bool estimation = parsed.options.task == "estimation";
    const std::string task = parsed.options.task;
    const bool design = task == "design", monte = task == "monte_carlo";
    const Relower relower = [&](const std::vector<std::string>& parameters) {
      const auto mark = diags.mark();  // reported once already
      std::optional<symbolic::OdeModel> again = lower_model(flat, diags);
      diags.rollback(mark);
      if (!again) throw std::logic_error("the study's model did not lower a second time");
      add_measured_outputs(*again, measured_names(parsed.options, cli.study_file));
      if (auto error = add_named_sensitivities(*again, parameters); !error.empty()) throw UsageError(error);
      return std::move(*again);
    };
    if (!mpi_world().root() && !monte) return 0;  // rank 0 solves it
    const int status =
        estimation ? estimation_with_events(flat, cli, parsed.options, std::move(*problem), *ode, diags, relower)
        : design   ? design_with_events(flat, cli, std::move(parsed.options), std::move(*problem), *ode, diags)
        : monte    ? monte_carlo_with_events(flat, cli, std::move(parsed.options), std::move(*problem), *ode, diags)
                   : optimal_control_with_events(flat, cli, std::move(parsed.options), std::move(*problem), *ode, diags);
    if (cli.run) record_timings(cli.output, cli.run->timings);
    return status;
  }
  symbolic::LoopExposure loops;
  std::unique_ptr<BuiltModel> newton;
  if (parsed.options.task == "optimal_control" && parsed.options.nonlinear_blocks == "nlp") {
    loops = symbolic::expose_nonlinear_blocks(*ode);
    if (!loops.inputs.empty() && parsed.options.init_traj) {
      std::optional<symbolic::OdeModel> original = lower_model(flat, diags);  // Newton kept
      if (!original) return 1;
      std::vector<std::string> variables;
      for (const auto& li : loops.inputs) variables.push_back(li.variable);
      add_measured_outputs(*original, variables);
      newton = std::make_unique<BuiltModel>(build_model(*original, cli.jobs, "morun", cli.run, cli.quiet));
    }
  }
  Study s{flat, cli, std::move(parsed.options), std::move(*problem),
          build_model(*ode, cli.jobs, "morun", cli.run, cli.quiet), std::move(loops), std::move(newton)};
  fs::create_directories(cli.output);
  if (!world.root() && s.opt.task != "design" && s.opt.task != "monte_carlo") return 0;  // rank 0 solves it
  const int status = s.opt.task == "design"        ? design(s)
                     : s.opt.task == "estimation"  ? estimation(s)
                     : s.opt.task == "monte_carlo" ? monte_carlo(s)
                                                   : optimal_control(s);
  if (cli.run && world.root()) record_timings(cli.output, cli.run->timings);
  return status;
}

}  // namespace mo::tools
