// morun: Modelica model → simulation results in one command.
//
//   flatten ─ lower ─ generate C++ ─ compile (cached) ─ dlopen ─ simulate
//   ─ DIR/result.csv, DIR/summary.json (atomically) [, DIR/*.png]
//
// Exit status: 0 success, 1 errors in the model or the simulation failed,
// 2 bad command line, 3 internal error.
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "mo/codegen/generate.hpp"
#include "mo/codegen/shared_object.hpp"
#include "mo/frontend/diagnostics.hpp"
#include "mo/runtime/simulate.hpp"
#include "pipeline.hpp"

namespace fs = std::filesystem;
using namespace mo;

namespace {

struct Options {
  tools::ModelSource source;
  double stop_time = 1.0;
  std::size_t intervals = 500;
  std::vector<std::string> sets;        // p=v
  std::vector<std::string> input_specs; // u=sine:amp,freq | u=csv:file | u=const:v
  std::vector<std::string> sensitivities;
  std::string output = "results";
  bool plot = false;
  unsigned jobs = 2;
  double rtol = 1e-6, atol = 1e-8;
};

/// A command-line problem: printed as "morun: error: ..." with exit status 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::pair<std::string, std::string> split_assignment(const std::string& s, const char* what) {
  const auto eq = s.find('=');
  if (eq == std::string::npos || eq == 0)
    throw UsageError(fmt::format("{} '{}' is not of the form name=value", what, s));
  return {s.substr(0, eq), s.substr(eq + 1)};
}

double number(const std::string& s, const std::string& context) {
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used == s.size()) return v;
  } catch (const std::exception&) {
  }
  throw UsageError(fmt::format("'{}' in {} is not a number", s, context));
}

std::vector<double> parameters(const runtime::ModelInfo& info, const Options& opt) {
  std::vector<double> p = info.default_parameters();
  for (const auto& s : opt.sets) {
    auto [name, value] = split_assignment(s, "--set");
    const auto k = info.parameter_index(name);
    if (!k) throw UsageError("--set: the model has no parameter '" + name + "'");
    p[*k] = number(value, "--set " + s);
  }
  return p;
}

/// u=sine:amp,freq | u=csv:file.csv (column named u) | u=const:value.
std::unique_ptr<runtime::InputSignal> signal(const std::string& name, const std::string& spec) {
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon), args = colon == std::string::npos ? "" : spec.substr(colon + 1);
  if (kind == "sine") {
    const auto comma = args.find(',');
    if (comma == std::string::npos) throw UsageError("--input " + name + "=sine:AMPLITUDE,FREQUENCY_HZ");
    return runtime::sine_input(number(args.substr(0, comma), "--input " + name),
                               number(args.substr(comma + 1), "--input " + name));
  }
  if (kind == "const") return runtime::constant_input(number(args, "--input " + name));
  if (kind == "csv") {
    auto table = std::make_shared<const runtime::InputTable>(runtime::read_input_csv(args));
    try {
      return runtime::table_input(table, name);
    } catch (const std::out_of_range&) {
      throw UsageError("--input: " + args + " has no column named '" + name + "'");
    }
  }
  throw UsageError("--input " + name + ": unknown signal '" + kind + "' (sine, csv, const)");
}

runtime::Inputs inputs(const runtime::ModelInfo& info, const Options& opt) {
  std::vector<std::unique_ptr<runtime::InputSignal>> signals(info.inputs.size());
  for (const auto& s : opt.input_specs) {
    auto [name, spec] = split_assignment(s, "--input");
    const auto k = info.input_index(name);
    if (!k) throw UsageError("--input: the model has no input '" + name + "'");
    signals[*k] = signal(name, spec);
  }
  for (std::size_t i = 0; i < signals.size(); ++i)
    if (!signals[i])
      throw UsageError("the model's input '" + info.inputs[i].name + "' needs a signal: --input " +
                       info.inputs[i].name + "=sine:AMPLITUDE,FREQ | csv:FILE | const:VALUE");
  return runtime::Inputs(std::move(signals));
}

/// The full path of `program` on PATH, or empty.
std::string find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::string all = path ? path : "";
  for (std::size_t start = 0; start <= all.size();) {
    const auto end = std::min(all.find(':', start), all.size());
    const fs::path candidate = fs::path(all.substr(start, end - start)) / program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    start = end + 1;
  }
  return {};
}

/// One PNG per group (states, outputs) of result.csv, by gnuplot.
void plot(const std::string& dir, const runtime::SimulationResult& r, const runtime::ModelInfo& info) {
  const std::string gnuplot = find_on_path("gnuplot");
  if (gnuplot.empty()) throw std::runtime_error("--plot needs gnuplot, which is not on PATH");
  const std::string script_path = (fs::path(dir) / "plot.gp").string();
  std::ofstream gp(script_path);
  gp << "set datafile separator ','\nset terminal pngcairo size 1000,600\nset xlabel 'time'\n"
        "set key outside right\n";
  auto group = [&](const std::string& file, std::size_t first, std::size_t count) {
    if (count == 0) return;
    gp << "set output '" << (fs::path(dir) / file).string() << "'\nplot ";
    for (std::size_t k = 0; k < count; ++k)  // column titles from the header, never pasted as text
      gp << (k ? ", " : "") << "'" << (fs::path(dir) / "result.csv").string() << "' using 1:" << first + k + 2
         << " with lines title columnhead";
    gp << "\n";
  };
  group("states.png", 0, info.num_base_states());
  group("outputs.png", info.states.size(), info.outputs.size());
  gp.close();
  (void)r;
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execl(gnuplot.c_str(), "gnuplot", script_path.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) throw std::runtime_error("gnuplot failed on " + script_path);
}

int run(const Options& opt) {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  auto flat = tools::load_flat_model(opt.source, sources, diags);
  if (!flat) {
    diags.print(std::cerr);
    return 1;
  }
  auto ode = tools::lower_model(*flat, diags);
  diags.print(std::cerr);
  if (!ode) return 1;
  if (auto error = tools::add_named_sensitivities(*ode, opt.sensitivities); !error.empty())
    throw UsageError(error);
  const auto generated = codegen::generate_cpp(*ode);
  codegen::CompilerOptions co = codegen::runtime_compiler_options();
  co.jobs = opt.jobs;
  const auto compiled = codegen::compile_shared_object(generated, co);
  if (compiled.cached)
    std::cerr << "morun: model cached (" << compiled.library << ")\n";
  else
    std::cerr << fmt::format("morun: model compiled in {:.2f} s ({} instructions, {} files)\n",
                             compiled.seconds, generated.instructions, generated.sources().size());
  auto model = codegen::LoadedModel(compiled.library, generated.factory_symbol).create();
  const runtime::ModelInfo& info = model->info();
  const std::vector<double> p = parameters(info, opt);
  runtime::SimulationOptions so;
  so.relative_tolerance = opt.rtol;
  so.absolute_tolerance = opt.atol;
  if (!opt.sensitivities.empty()) so.sensitivities.method = runtime::SensitivityMethod::model_states;
  const auto result = runtime::simulate(*model, inputs(info, opt),
                                        p, runtime::OutputGrid::uniform(0.0, opt.stop_time, opt.intervals), so);
  fs::create_directories(opt.output);
  runtime::write_csv_atomic((fs::path(opt.output) / "result.csv").string(), result.trajectory);
  nlohmann::json summary = nlohmann::json::parse(runtime::summary_json(result));
  summary["model"] = info.name;
  summary["compile"] = {{"cached", compiled.cached}, {"seconds", compiled.seconds},
                        {"library", compiled.library}, {"key", compiled.key}};
  runtime::write_file_atomic((fs::path(opt.output) / "summary.json").string(),
                             [&](std::ostream& os) { os << summary.dump(2) << "\n"; });
  if (!model->last_failure().empty()) std::cerr << "morun: model: " << model->last_failure() << "\n";
  if (!result.ok()) {
    std::cerr << "morun: simulation failed: " << runtime::to_string(result.status) << ": "
              << result.message << "\n";
    return 1;
  }
  if (opt.plot) plot(opt.output, result, info);
  std::cerr << fmt::format("morun: simulated to t = {} in {:.3f} s; results in {}\n", opt.stop_time,
                           result.statistics.wall_time_seconds, opt.output);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"morun — compile a Modelica model to C++, build it (cached) and simulate it.\n"
               "Writes DIR/result.csv (states, outputs) and DIR/summary.json."};
  app.set_version_flag("--version", "morun 0.1.0");
  Options opt;
  app.add_option("file", opt.source.file, "Modelica file holding the class")->required()->check(CLI::ExistingFile);
  app.add_option("-c,--class", opt.source.class_name, "Class to simulate (default: the last class in FILE)");
  app.add_option("-L,--library", opt.source.libs, "Library file or directory (repeatable)")->check(CLI::ExistingPath);
  app.add_option("--stop-time", opt.stop_time, "Final time (start is 0)")->required()->check(CLI::PositiveNumber);
  app.add_option("--intervals", opt.intervals, "Output intervals")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--set", opt.sets, "Parameter value p=v (repeatable)");
  app.add_option("--input", opt.input_specs, "Input signal u=sine:AMP,FREQ_HZ | u=csv:FILE | u=const:V (repeatable)");
  app.add_option("--sensitivities", opt.sensitivities, "Parameters to compute forward sensitivities for")
      ->delimiter(',');
  app.add_option("-o,--output", opt.output, "Result directory")->capture_default_str();
  app.add_flag("--plot", opt.plot, "Also write PNG plots (needs gnuplot)");
  app.add_option("-j,--jobs", opt.jobs, "Compile this many generated files in parallel")->capture_default_str();
  app.add_option("--rtol", opt.rtol, "Relative tolerance")->capture_default_str();
  app.add_option("--atol", opt.atol, "Absolute tolerance (scaled by nominal values)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    return run(opt);
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
