// Shared tool helpers; see common.hpp.
#include "common.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>

#include "mo/codegen/generate.hpp"

namespace fs = std::filesystem;

namespace mo::tools {

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

namespace {

std::pair<double, double> two_numbers(const std::string& args, const std::string& context) {
  const auto comma = args.find(',');
  if (comma == std::string::npos) throw UsageError(context + " needs two numbers A,B");
  return {number(args.substr(0, comma), context), number(args.substr(comma + 1), context)};
}

}  // namespace

std::unique_ptr<runtime::InputSignal> parse_signal(const std::string& name, const std::string& spec) {
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string args = colon == std::string::npos ? "" : spec.substr(colon + 1);
  const std::string context = "input " + name + "=" + spec;
  if (kind == "sine") {
    const auto [amplitude, frequency] = two_numbers(args, context);
    return runtime::sine_input(amplitude, frequency);
  }
  if (kind == "step") {
    const auto [height, time] = two_numbers(args, context);
    return runtime::step_input(height, time);
  }
  if (kind == "const") return runtime::constant_input(number(args, context));
  if (kind == "csv" || kind == "pwc") {
    auto table = runtime::read_result_table(args);  // CSV, Dymola text or .mat
    const auto it = std::find(table.names.begin(), table.names.end(), name);
    if (it == table.names.end())
      throw UsageError(context + ": " + args + " has no column named '" + name + "'");
    if (kind == "pwc") {
      const auto& column = table.columns[static_cast<std::size_t>(it - table.names.begin())];
      return runtime::piecewise_constant_input(table.times, column);
    }
    return runtime::table_input(std::make_shared<const runtime::InputTable>(std::move(table)), name);
  }
  throw UsageError(context + ": unknown signal '" + kind + "' (sine, step, const, csv, pwc)");
}

BuiltModel build_model(symbolic::OdeModel& ode, unsigned jobs, const std::string& tool,
                       RunContext* run, bool quiet) {
  std::optional<codegen::GeneratedSources> generated_storage;
  {
    PhaseScope phase(run, "generate", fmt::format("C++ for {} states", ode.states.size()));
    generated_storage.emplace(codegen::generate_cpp(ode));
  }
  const auto& generated = *generated_storage;
  codegen::CompilerOptions co = codegen::runtime_compiler_options();
  co.jobs = jobs;
  BuiltModel out;
  {
    PhaseScope phase(run, "compile", fmt::format("{} files, {} jobs", generated.sources().size(), jobs));
    out.compiled = codegen::compile_shared_object(generated, co);
  }  // the status line is gone before the note below
  if (!quiet && out.compiled.cached)
    std::cerr << tool << ": model cached (" << out.compiled.library << ")\n";
  else if (!quiet)
    std::cerr << fmt::format("{}: model compiled in {:.2f} s ({} instructions, {} files)\n", tool,
                             out.compiled.seconds, generated.instructions,
                             generated.sources().size());
  out.library = std::make_unique<codegen::LoadedModel>(out.compiled.library, generated.factory_symbol);
  out.model = out.library->create();
  return out;
}

std::string find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  const std::string all = path ? path : "";
  for (std::size_t start = 0; start <= all.size();) {
    const auto end = std::min(all.find(':', start), all.size());
    const fs::path candidate = fs::path(all.substr(start, end - start)) / program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    start = end + 1;
  }
  return {};
}

void run_gnuplot(const std::string& script_path) {
  const std::string gnuplot = find_on_path("gnuplot");
  if (gnuplot.empty()) throw std::runtime_error("plots need gnuplot, which is not on PATH");
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execl(gnuplot.c_str(), "gnuplot", script_path.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("gnuplot failed on " + script_path);
}

}  // namespace mo::tools
