// Helpers shared by the command-line tools: command-line errors, input
// signal specifications, building a lowered model into a loaded Model, and
// running gnuplot.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "mo/codegen/shared_object.hpp"
#include "mo/runtime/input.hpp"
#include "mo/runtime/model.hpp"
#include "mo/symbolic/ode.hpp"
#include "progress.hpp"

namespace mo::tools {

/// A command-line problem: printed as "<tool>: error: ..." with exit status 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// "name=value" split at the first '='; UsageError naming `what` otherwise.
std::pair<std::string, std::string> split_assignment(const std::string& s, const char* what);

/// The number `s` (all of it); UsageError mentioning `context` otherwise.
double number(const std::string& s, const std::string& context);

/// An input signal from "sine:AMP,FREQ_HZ", "const:V", "step:HEIGHT,T",
/// "csv:FILE" (column named `name`) or "pwc:FILE" (piecewise constant, the
/// same CSV). UsageError on a bad specification, InputFileError on a bad file.
std::unique_ptr<runtime::InputSignal> parse_signal(const std::string& name, const std::string& spec);

/// A model compiled (or found in the cache) and loaded.
struct BuiltModel {
  std::unique_ptr<codegen::LoadedModel> library;  ///< keeps the shared object loaded
  std::unique_ptr<runtime::Model> model;          ///< an instance
  codegen::CompiledModel compiled;                ///< cache key, time, path
};

/// Generates C++ for `ode`, compiles it with `jobs` parallel jobs (cached by
/// content hash), loads it and prints one line ("compiled in" / "cached") to
/// stderr prefixed with `tool` (unless `quiet`). With `run`, the generate and
/// compile phases show progress and are timed. Throws codegen::CompileError on failure.
BuiltModel build_model(symbolic::OdeModel& ode, unsigned jobs, const std::string& tool,
                       RunContext* run = nullptr, bool quiet = false);

/// The full path of `program` on PATH, or empty.
std::string find_on_path(const std::string& program);

/// Runs gnuplot on `script_path`; std::runtime_error if gnuplot is missing or fails.
void run_gnuplot(const std::string& script_path);

}  // namespace mo::tools
