// morun: Modelica model → simulation results in one command.
//
//   flatten ─ lower ─ generate C++ ─ compile (cached) ─ dlopen ─ simulate
//   ─ DIR/result.csv, DIR/summary.json (atomically) [, DIR/*.png]
//
// Exit status: 0 success, 1 errors in the model or the simulation failed,
// 2 bad command line, 3 internal error.

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>

#include "mo/codegen/generate.hpp"
#include "mo/codegen/shared_object.hpp"
#include "mo/frontend/diagnostics.hpp"
#include "mo/runtime/simulate.hpp"
#include "common.hpp"
#include "measured_outputs.hpp"
#include "pipeline.hpp"
#include "failure_diagnosis.hpp"
#include "plot.hpp"
#include "progress.hpp"
#include "xcos_init.hpp"
#include "result_columns.hpp"
#include "parallel_runner.hpp"
#include "study.hpp"
#include "diagram_cli.hpp"

namespace fs = std::filesystem;
using namespace mo;

namespace {

struct Options {
  tools::ModelSource source;
  tools::StudyCli study;
  double stop_time = 0.0;
  std::size_t intervals = 500;
  std::vector<std::string> sets;        // p=v
  std::vector<std::string> input_specs; // u=sine:amp,freq | u=csv:file | u=const:v
  std::vector<std::string> sensitivities;
  std::string output = "results";
  bool plot = false;
  unsigned jobs = 2;
  double rtol = 1e-6, atol = 1e-8;
  std::string linear_solver = "auto";  // auto, dense or klu
  std::vector<std::string> measure;  // outputs sampled into measurements.csv
  double noise = 0.0;                // their noise standard deviation
  unsigned long seed = 1;            // of the noise
  bool aliases = false;              // accepted for compatibility: result.csv has every variable
  std::string variables;             // regular expression selecting result.csv's columns
  bool quiet = false;                // no progress on stderr
  tools::DiagramOptions diagram;     // FILE is an Xcos diagram: how to run Scilab
  bool from_diagram = false;         // source.file is the flat file Scilab wrote for it
  std::string init_file;             // the diagram's <title>_imf_init.xml, or empty
};

using tools::number;
using tools::split_assignment;
using tools::UsageError;

/// Why `name`, a component of the flat model, is not a parameter of the
/// compiled one; empty if the flat model does not know it either.
std::string why_not_a_parameter(const frontend::flat::Model& flat, const std::string& name) {
  const std::int32_t i = flat.find(name);
  if (i < 0) return {};
  const frontend::flat::Variable& v = flat.variables[static_cast<std::size_t>(i)];
  if (v.variability == frontend::ast::Variability::Constant) return ": it is a constant";
  if (v.variability != frontend::ast::Variability::Parameter) return ": it is a variable, not a parameter";
  if (v.evaluate)
    return ": annotation(Evaluate = true) made its value part of the model's structure when it was "
           "translated; change it in the model";
  if (v.type != frontend::flat::BaseType::Real)
    return ": a Boolean, Integer or enumeration parameter is part of the model's structure; change it in "
           "the model";
  if (v.binding) return ": it is bound to other parameters' values; set those";
  return {};
}

std::vector<double> parameters(const runtime::ModelInfo& info, const frontend::flat::Model& flat,
                               const Options& opt) {
  std::vector<double> p = info.default_parameters();
  for (const auto& s : opt.sets) {
    auto [name, value] = split_assignment(s, "--set");
    const auto k = info.parameter_index(name);
    if (!k) throw UsageError("--set: the model has no parameter '" + name + "'" + why_not_a_parameter(flat, name));
    p[*k] = number(value, "--set " + s);
  }
  return p;
}

runtime::Inputs inputs(const runtime::ModelInfo& info, const Options& opt) {
  std::vector<std::unique_ptr<runtime::InputSignal>> signals(info.inputs.size());
  for (const auto& s : opt.input_specs) {
    auto [name, spec] = split_assignment(s, "--input");
    const auto k = info.input_index(name);
    if (!k) throw UsageError("--input: the model has no input '" + name + "'");
    signals[*k] = tools::parse_signal(name, spec);
  }
  // An undriven input is 0 (a warning names them all), so the model still runs.
  std::string undriven;
  for (std::size_t i = 0; i < signals.size(); ++i)
    if (!signals[i]) {
      undriven += (undriven.empty() ? "'" : ", '") + info.inputs[i].name + "'";
      signals[i] = runtime::constant_input(0.0);
    }
  if (!undriven.empty())
    std::cerr << "morun: warning: undriven input" << (undriven.find(',') != std::string::npos ? "s " : " ")
              << undriven << " set to 0 (drive with --input NAME=sine:AMP,FREQ | step:H,T | const:V | "
              << "csv:FILE | pwc:FILE)\n";
  return runtime::Inputs(std::move(signals));
}

/// DIR/measurements.csv: the --measure outputs at the output times after t0,
/// each plus white noise of standard deviation --noise (seeded by --seed).
void write_measurements(const Options& opt, const runtime::ModelInfo& info,
                        const runtime::ResultTable& trajectory) {
  std::vector<std::size_t> columns;
  for (const auto& name : opt.measure) {
    const auto k = info.output_index(name);
    if (!k) throw UsageError("--measure: the model has no variable '" + name + "'");
    columns.push_back(info.states.size() + *k);
  }
  std::mt19937_64 rng(opt.seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  runtime::ResultTable out(opt.measure);
  for (std::size_t row = 1; row < trajectory.rows(); ++row) {
    std::vector<double> values;
    for (std::size_t c : columns) values.push_back(trajectory.at(row, c) + opt.noise * noise(rng));
    out.add_row(trajectory.times()[row], values);
  }
  runtime::write_csv_atomic((fs::path(opt.output) / "measurements.csv").string(), out);
}

/// Re-evaluates the model at the state of row `k` of the trajectory (the
/// row before if its states are not finite) so that it records why it gave
/// non-finite values (the caller prints model.last_failure()), and returns
/// the equation that produced the first non-finite value there, if one did.
std::string model_failure_at(runtime::Model& model, const symbolic::OdeModel& ode, runtime::Inputs in,
                             const std::vector<double>& p, const runtime::ResultTable& trajectory,
                             std::size_t k) {
  const std::size_t n = model.info().states.size();
  auto states_finite = [&](std::size_t row) {
    for (std::size_t i = 0; i < n; ++i)
      if (!std::isfinite(trajectory.at(row, i))) return false;
    return true;
  };
  if (!states_finite(k) && k > 0) --k;
  const double t = trajectory.times()[k];
  std::vector<double> x(n), u(model.info().inputs.size()), y(model.info().outputs.size());
  for (std::size_t i = 0; i < n; ++i) x[i] = trajectory.at(k, i);
  in.evaluate(t, u);
  model.outputs(t, x, u, p, y);
  const std::span<const double> d = model.discrete();
  return tools::explain_non_finite(ode, t, x, u, p, d);
}

int run(const Options& opt, tools::RunContext& ctx) {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  std::unique_ptr<frontend::flat::Model> flat;
  {
    tools::PhaseScope phase(&ctx, "flatten", opt.source.file);
    flat = tools::load_flat_model(opt.source, sources, diags);
  }
  if (!flat) {
    diags.print(std::cerr);
    return 1;
  }
  if (opt.from_diagram) {
    if (const auto note = tools::apply_diagram_init(*flat, opt.init_file, "morun"); !note.empty())
      std::cerr << note << "\n";
    if (const auto note = tools::diagram_inputs_note(*flat, "morun"); !note.empty()) std::cerr << note << "\n";
  }
  if (flat->optimization) {
    for (const auto& [given, flag] : {std::pair{opt.stop_time > 0, "--stop-time"},
                                      {!opt.input_specs.empty(), "--input"},
                                      {!opt.measure.empty(), "--measure"},
                                      {!opt.sensitivities.empty(), "--sensitivities"}})
      if (given)
        std::cerr << "morun: warning: " << flag << " is for simulating a model; a study ignores it "
                     "(use the study's options, --option name=value)\n";
    return tools::run_study(*flat, opt.study, diags);
  }
  if (opt.stop_time <= 0) throw UsageError("--stop-time is required to simulate a model");
  std::optional<symbolic::OdeModel> ode;
  std::size_t declared_outputs = 0;
  {
    tools::PhaseScope phase(&ctx, "lower", flat->name);
    ode = tools::lower_model(*flat, diags);
    diags.print(std::cerr);
    if (!ode) return 1;
    tools::expose_start_parameters(*ode, opt.sets);  // --set x.start=v
    tools::expose_start_parameters(*ode, opt.sensitivities);
    const std::size_t model_algebraics = ode->algebraics.size();
    if (const auto unknown = tools::add_measured_outputs(*ode, opt.measure); !unknown.empty())
      throw UsageError("--measure: the model has no variable '" + unknown.front() + "'");
    if (auto error = tools::add_named_sensitivities(*ode, opt.sensitivities); !error.empty())
      throw UsageError(error);
    declared_outputs = ode->outputs.size();
    // every variable of the model is a column of result.csv (as extra outputs)
    tools::add_all_variables(*ode, model_algebraics);
  }
  std::optional<std::regex> filter;
  if (!opt.variables.empty()) try {
      filter.emplace(opt.variables, std::regex::ECMAScript);
    } catch (const std::regex_error& e) {
      throw UsageError("--variables: '" + opt.variables + "' is not a regular expression: " + e.what());
    }
  tools::BuiltModel built = tools::build_model(*ode, opt.jobs, "morun", &ctx, opt.quiet);
  const auto& compiled = built.compiled;
  runtime::Model* model = built.model.get();
  const runtime::ModelInfo& info = model->info();
  const std::vector<double> p = parameters(info, *flat, opt);
  runtime::SimulationOptions so;
  so.relative_tolerance = opt.rtol;
  so.absolute_tolerance = opt.atol;
  so.linear_solver = opt.linear_solver == "klu"     ? runtime::LinearSolverChoice::sparse
                     : opt.linear_solver == "dense" ? runtime::LinearSolverChoice::dense
                                                    : runtime::LinearSolverChoice::automatic;
  if (!opt.sensitivities.empty()) so.sensitivities.method = runtime::SensitivityMethod::model_states;
  // Every requested parameter, so that one without sensitivity states is
  // reported by simulate() instead of silently missing from the columns.
  for (const auto& name : opt.sensitivities)
    if (const auto k = info.parameter_index(name)) so.sensitivities.parameters.push_back(*k);
  runtime::SimulationResult result;
  {
    tools::PhaseScope phase(&ctx, "simulate", fmt::format("t = 0 .. {}", opt.stop_time));
    result = runtime::simulate(*model, inputs(info, opt), p,
                               runtime::OutputGrid::uniform(0.0, opt.stop_time, opt.intervals), so);
  }
  // NaN or infinity never reaches result.csv: rows from the first one on are
  // dropped and the run fails, naming the variables and the model's reason.
  runtime::SimulationResult checked = result;
  if (const auto bad = tools::first_non_finite_row(result.trajectory)) {
    const double t = result.trajectory.times()[*bad];
    checked.trajectory = tools::first_rows(result.trajectory, *bad);
    if (result.ok()) {
      checked.status = runtime::SimulationStatus::rhs_failure;
      checked.message = fmt::format("non-finite values at t = {} in {}", t,
                                    tools::non_finite_columns(result.trajectory, *bad));
      const std::string where = model_failure_at(*model, *ode, inputs(info, opt), p, result.trajectory, *bad);
      if (!where.empty()) checked.message += "\n  from " + where;
    }
  }
  // (Only when the simulator itself failed: a NaN in a row of a successful
  // run is explained above.)
  using Status = runtime::SimulationStatus;
  const bool integrator_gave_up =
      result.status == Status::too_much_work || result.status == Status::error_test_failure ||
      result.status == Status::convergence_failure || result.status == Status::rhs_failure;
  if (integrator_gave_up && result.non_finite_rhs) {
    // Name the equation of the last non-finite value the integrator met on
    // its way (a step it tried and rejected): most likely why it gave up.
    const auto& bad = *result.non_finite_rhs;
    const std::string where = tools::explain_non_finite(*ode, bad.t, bad.x, bad.u, p, model->discrete());
    if (!where.empty())
      checked.message += fmt::format("\n  the right-hand side was not finite at t = {} (a step the "
                                     "integrator tried), from {}", bad.t, where);
  }
  fs::create_directories(opt.output);
  runtime::write_csv_atomic((fs::path(opt.output) / "result.csv").string(),
                            tools::select_columns(checked.trajectory, filter));
  if (!opt.measure.empty() && checked.ok()) write_measurements(opt, info, checked.trajectory);
  nlohmann::json summary = nlohmann::json::parse(runtime::summary_json(checked));
  summary["model"] = info.name;
  summary["compile"] = {{"cached", compiled.cached}, {"seconds", compiled.seconds},
                        {"library", compiled.library}, {"key", compiled.key}};
  summary["units"] = tools::unit_map(info);
  summary["timings_seconds"] = ctx.timings.json();
  runtime::write_file_atomic((fs::path(opt.output) / "summary.json").string(),
                             [&](std::ostream& os) { os << summary.dump(2) << "\n"; });
  if (!model->last_failure().empty()) std::cerr << "morun: model: " << model->last_failure() << "\n";
  for (const auto& w : checked.warnings) std::cerr << "morun: warning: " << w << "\n";
  if (!checked.ok()) {
    std::cerr << "morun: simulation failed: " << runtime::to_string(checked.status) << ": "
              << checked.message << "\n";
    if (checked.trajectory.rows() > 0)
      std::cerr << fmt::format("morun: result.csv holds the {} rows up to t = {}\n", checked.trajectory.rows(),
                               checked.trajectory.times().back());
    return 1;
  }
  if (opt.plot) tools::plot_simulation(opt.output, info, declared_outputs);
  if (checked.status == runtime::SimulationStatus::terminated_by_model)
    std::cerr << "morun: " << checked.message << "\n";
  std::cerr << fmt::format("morun: simulated to t = {} in {:.3f} s; results in {}\n",
                           checked.trajectory.rows() > 0 ? checked.trajectory.times().back() : opt.stop_time,
                           result.statistics.wall_time_seconds, opt.output);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"morun — compile a Modelica model to C++, build it (cached) and simulate it; or\n"
               "run a study (an Optimica optimization class: optimal control, input design,\n"
               "parameter estimation). Writes DIR/result.csv or DIR/trajectories.csv, and\n"
               "DIR/summary.json."};
  app.set_version_flag("--version", "morun 0.1.0");
  Options opt;
  app.add_option("file", opt.source.file,
                 "Modelica file holding the class, or an Xcos diagram (.zcos, .xcos: compiled to flat "
                 "Modelica by Scilab first)")->required()->check(CLI::ExistingFile);
  app.add_option("-c,--class", opt.source.class_name, "Class to simulate (default: the last class in FILE)");
  app.add_option("-L,--library", opt.source.libs, "Library file or directory (repeatable)")->check(CLI::ExistingPath);
  app.add_option("--stop-time", opt.stop_time, "Final time (start is 0); required for a model, not for a study")
      ->check(CLI::PositiveNumber);
  app.add_option("--option", opt.study.overrides_text,
                 "Study: override a __mocompile option, name=value (repeatable), e.g. n_cp=1");
  app.add_option("--intervals", opt.intervals, "Output intervals")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--set", opt.sets,
                 "Parameter value p=v, or a state's start value x.start=v (repeatable)");
  app.add_option("--input", opt.input_specs, "Input signal u=sine:AMP,FREQ_HZ | step:HEIGHT,TIME | const:V | csv:FILE (interpolated) | "
                 "pwc:FILE (piecewise constant) (repeatable)");
  app.add_option("--sensitivities", opt.sensitivities,
                 "Parameters (or x.start for a state's start value) to compute forward sensitivities for")
      ->delimiter(',');
  app.add_option("-o,--output", opt.output, "Result directory")->capture_default_str();
  app.add_flag("--aliases", opt.aliases,
               "Accepted for compatibility: result.csv always holds every variable, eliminated aliases included");
  app.add_option("--variables", opt.variables,
                 "Only the result.csv columns whose flat names match this regular expression (all of the name)");
  app.add_flag("--plot", opt.plot, "Also write plots, PNG and SVG (needs gnuplot)");
  app.add_flag("-q,--quiet", opt.quiet,
               "No progress on stderr (by default work longer than 2 s reports its stage, at most once a second)");
  opt.jobs = tools::default_jobs();
  app.add_option("-j,--jobs", opt.jobs,
                 "Parallel jobs: generated files compiled at once, and worker processes for the starts of a "
                 "design and the runs of a Monte-Carlo study (default: the number of cores)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--measure", opt.measure,
                 "Also write DIR/measurements.csv: these variables (outputs, states, algebraic variables, aliases) at the output times after 0")
      ->delimiter(',');
  app.add_option("--noise", opt.noise, "Standard deviation of white noise added to --measure outputs")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--seed", opt.seed, "Seed of the --noise generator")->capture_default_str();
  app.add_option("--rtol", opt.rtol, "Relative tolerance")->capture_default_str();
  app.add_option("--atol", opt.atol, "Absolute tolerance (scaled by nominal values)")->capture_default_str();
  app.add_option("--linear-solver", opt.linear_solver,
                 "The integrator's linear solver: auto (KLU, sparse LU, from 100 states whose Jacobian is at most a "
                 "tenth full; dense LU below), dense or klu")
      ->check(CLI::IsMember({"auto", "dense", "klu"}))
      ->capture_default_str();
  tools::add_diagram_options(app, opt.diagram);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every command-line mistake exits 2.
    return app.exit(e) == 0 ? 0 : 2;
  }
  opt.study.output = opt.output;
  opt.study.sets = opt.sets;
  opt.study.study_file = opt.source.file;
  opt.study.jobs = opt.jobs;
  opt.study.plot = opt.plot;
  opt.study.quiet = opt.quiet;
  tools::Progress progress(std::cerr, tools::stderr_progress_options(opt.quiet, "morun"));
  tools::RunContext ctx;
  ctx.progress = &progress;
  opt.study.run = &ctx;
  std::unique_ptr<tools::ExtractedDiagram> diagram;  // its temporary folder lives until the end
  try {
    if (tools::is_diagram_file(opt.source.file)) {
      opt.diagram.tool = "morun";
      opt.diagram.quiet = true;  // the progress line shows the "diagram" stage
      std::vector<std::string> notes;
      {
        tools::PhaseScope phase(&ctx, "diagram", opt.source.file);
        diagram = tools::extract_flat_model(opt.source.file, opt.diagram);
        if (!opt.diagram.open_loop) notes = tools::close_diagram_loop(*diagram, opt.diagram.tool);
      }
      for (const auto& line : notes) std::cerr << line << "\n";
      opt.source.file = diagram->flat_file().string();
      if (opt.diagram.init_fixed) opt.init_file = diagram->init_file().string();
      opt.from_diagram = true;
    }
    return run(opt, ctx);
  } catch (const tools::DiagramError& e) {
    std::cerr << e.what() << "\n";
    return 1;
  } catch (const UsageError& e) {
    std::cerr << "morun: error: " << e.what() << "\n";
    return 2;
  } catch (const codegen::CompileError& e) {
    std::cerr << "morun: internal error: " << e.what() << "\n";
    return 3;
  } catch (const runtime::InputFileError& e) {
    std::cerr << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "morun: error: " << e.what() << "\n";
    return 1;
  }
}
