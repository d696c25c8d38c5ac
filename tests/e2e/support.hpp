// End-to-end helpers: a .mo file (with libraries) taken through the whole
// pipeline — parse, flatten, lower, (sensitivities), generate C++, compile
// into the shared test cache, dlopen — to a runtime::Model.
#pragma once

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "codegen/support.hpp"
#include "mo/codegen/generate.hpp"
#include "mo/codegen/shared_object.hpp"
#include "mo/runtime/model.hpp"
#include "mo/runtime/result.hpp"
#include "mo/runtime/simulate.hpp"
#include "mo/symbolic/evaluator.hpp"
#include "pipeline.hpp"
#include "result_columns.hpp"

namespace mo::e2e {

/// Where the repository's models live.
inline const std::string kModelica = std::string(MO_SOURCE_DIR) + "/modelica/";
/// Scilab's circuits and modelicat's flat files of them.
inline const std::string kScilab = std::string(MO_SOURCE_DIR) + "/tests/frontend/data/scilab/";
/// The e2e suite's own .mo models.
inline const std::string kData = std::string(MO_TEST_DATA_DIR) + "/";

/// What to build: the model's source and the parameters to append forward
/// sensitivities for (none: the plain model).
struct ModelSpec {
  tools::ModelSource source;
  std::vector<std::string> sensitivities;
  bool all_variables = false;  ///< every variable a result column, as in morun's result.csv
};

/// Flattens, lowers and (optionally) augments `spec`; FAILs the test with
/// the diagnostics if the pipeline rejects the model.
inline symbolic::OdeModel lower_spec(const ModelSpec& spec) {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  std::ostringstream printed;
  auto flat = tools::load_flat_model(spec.source, sources, diags);
  std::optional<symbolic::OdeModel> ode;
  if (flat) ode = tools::lower_model(*flat, diags);
  diags.print(printed);
  INFO("pipeline diagnostics for " << spec.source.file << ":\n" << printed.str());
  REQUIRE(ode);
  if (spec.all_variables) tools::add_all_variables(*ode, ode->algebraics.size());
  const std::string error = tools::add_named_sensitivities(*ode, spec.sensitivities);
  INFO(error);
  REQUIRE(error.empty());
  return std::move(*ode);
}

/// A model compiled and loaded once per process, with the lowered model it
/// came from (for variables that lowering eliminated from the results).
struct CompiledEntry {
  std::unique_ptr<codegen::LoadedModel> loaded;
  std::unique_ptr<symbolic::OdeModel> lowered;
};

/// The process-wide table behind compiled_model(), by name.
inline std::map<std::string, CompiledEntry>& compiled_entries() {
  static std::map<std::string, CompiledEntry> entries;
  return entries;
}

/// The model of `spec` generated, compiled (or found in the shared test
/// cache) and loaded once per process under `name` (a C++ identifier, unique
/// per spec); each call returns a fresh instance.
inline std::unique_ptr<runtime::Model> compiled_model(const std::string& name, const ModelSpec& spec) {
  auto& entry = compiled_entries()[name];
  if (!entry.loaded) {
    entry.lowered = std::make_unique<symbolic::OdeModel>(lower_spec(spec));
    codegen::CodegenOptions options;
    options.name = name;
    const codegen::GeneratedSources generated = codegen::generate_cpp(*entry.lowered, options);
    const codegen::CompiledModel so =
        codegen::compile_shared_object(generated, codegen::test::test_compiler_options());
    entry.loaded = std::make_unique<codegen::LoadedModel>(so.library, generated.factory_symbol);
  }
  return entry.loaded->create();
}

/// The folder ../shared beside the checkout, else $MO_SHARED_DIR; empty if
/// neither has third_party/ (the tests that read it are then skipped).
inline std::string shared_third_party_dir() {
  namespace fs = std::filesystem;
  if (fs::is_directory(fs::path(MO_SOURCE_DIR) / ".." / "shared" / "third_party"))
    return (fs::path(MO_SOURCE_DIR) / ".." / "shared").string();
  if (const char* env = std::getenv("MO_SHARED_DIR"); env && fs::is_directory(fs::path(env) / "third_party"))
    return env;
  return {};
}

/// MODELICAPATH set for the guard's lifetime, then restored.
class ModelicaPath {
public:
  explicit ModelicaPath(const std::string& path) {
    if (const char* before = std::getenv("MODELICAPATH")) saved_ = before;
    ::setenv("MODELICAPATH", path.c_str(), 1);
  }
  ~ModelicaPath() {
    if (saved_)
      ::setenv("MODELICAPATH", saved_->c_str(), 1);
    else
      ::unsetenv("MODELICAPATH");
  }
  ModelicaPath(const ModelicaPath&) = delete;
  ModelicaPath& operator=(const ModelicaPath&) = delete;

private:
  std::optional<std::string> saved_;
};

/// compiled_model() of a spec that reads the Modelica Standard Library 3.2.2 of
/// ../shared (beside the checkout, else $MO_SHARED_DIR), found by Modelica's
/// lookup on MODELICAPATH as a user runs it (restored afterwards); null, with
/// a "SKIPPED" warning, when there is no such folder.
inline std::unique_ptr<runtime::Model> msl_compiled_model(const std::string& name, const ModelSpec& spec) {
  const std::string shared = shared_third_party_dir();
  if (shared.empty()) {
    WARN("SKIPPED: no ../shared/third_party (set MO_SHARED_DIR)");
    return nullptr;
  }
  const ModelicaPath msl(shared + "/third_party/msl-3.2.2");
  return compiled_model(name, spec);
}

/// The values of variable `name` over a trajectory of model `model_name`
/// (compiled by compiled_model()) with parameters `p`: the result column if
/// there is one, else the value lowering recorded for the eliminated variable,
/// evaluated from the states, parameters and time of each row (no inputs).
inline std::vector<double> variable(const std::string& model_name, const runtime::ResultTable& table,
                                    std::span<const double> p, const std::string& name) {
  const auto& names = table.names();
  if (std::find(names.begin(), names.end(), name) != names.end()) return table.column(name);
  const symbolic::OdeModel& m = *compiled_entries().at(model_name).lowered;
  const auto it = std::find_if(m.eliminated.begin(), m.eliminated.end(),
                               [&](const symbolic::OdeOutput& e) { return e.info.name == name; });
  INFO("variable " << name << " of " << model_name);
  REQUIRE(it != m.eliminated.end());
  REQUIRE(m.inputs.empty());
  std::vector<double> out;
  for (std::size_t k = 0; k < table.rows(); ++k) {
    symbolic::LeafValues v;
    v[m.time] = table.times()[k];
    for (std::size_t i = 0; i < m.states.size(); ++i) v[m.states[i].symbol] = table.at(k, i);
    for (std::size_t i = 0; i < m.parameters.size(); ++i) v[m.parameters[i].symbol] = p[i];
    out.push_back(symbolic::evaluate(m.arena, std::span(&it->value, 1), v)[0]);
  }
  return out;
}

/// Index of parameter `name`; REQUIREs that it exists.
inline std::size_t parameter(const runtime::ModelInfo& info, const std::string& name) {
  const auto k = info.parameter_index(name);
  INFO("parameter " << name << " of " << info.name);
  REQUIRE(k);
  return *k;
}

/// Simulation options at rtol 1e-10, atol 1e-12 (comparisons with exact solutions).
inline runtime::SimulationOptions tight() {
  runtime::SimulationOptions o;
  o.relative_tolerance = 1e-10;
  o.absolute_tolerance = 1e-12;
  return o;
}

/// The discrete variable `name` as the model's last simulation (or
/// initialisation) left it; REQUIREs that it exists.
inline double discrete_value(runtime::Model& model, const std::string& name) {
  const auto& d = model.info().discrete;
  const auto it = std::find_if(d.begin(), d.end(), [&](const auto& v) { return v.name == name; });
  INFO("discrete variable " << name);
  REQUIRE(it != d.end());
  return model.discrete()[static_cast<std::size_t>(it - d.begin())];
}

/// The trajectory column `name`; REQUIREs that it exists.
inline std::vector<double> column(const runtime::ResultTable& table, const std::string& name) {
  const auto& names = table.names();
  INFO("column " << name);
  REQUIRE(std::find(names.begin(), names.end(), name) != names.end());
  return table.column(name);
}

/// Simulates `model` at its default parameters on `grid` (tight()), REQUIREs
/// success and CHECKs column `name` against `exact(t)` to `tolerance` at every
/// output time. Returns the result (event times, ...).
template <class Exact>
runtime::SimulationResult simulate_against_exact(runtime::Model& model, const runtime::OutputGrid& grid,
                                                 const std::string& name, Exact exact, double tolerance) {
  const auto r = runtime::simulate(model, {}, model.info().default_parameters(), grid, tight());
  INFO(r.message);
  REQUIRE(r.ok());
  const auto values = column(r.trajectory, name);
  for (std::size_t k = 0; k < grid.times.size(); ++k) {
    INFO(name << " at t = " << grid.times[k]);
    CHECK(std::fabs(values[k] - exact(grid.times[k])) < tolerance);
  }
  return r;
}

/// max_k |a_k - b_k|.
inline double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  REQUIRE(a.size() == b.size());
  double m = 0;
  for (std::size_t k = 0; k < a.size(); ++k) m = std::max(m, std::fabs(a[k] - b[k]));
  return m;
}

/// d(name)/d(p[k]) along `grid` by central differences of two simulations of
/// `model` at steps h and 2h, Richardson-extrapolated (error O(h^4)), at
/// rtol = atol = 1e-12; REQUIREs that every run succeeds.
inline std::vector<double> richardson_difference(runtime::Model& model, std::span<const double> p,
                                                 std::size_t k, double h, const runtime::OutputGrid& grid,
                                                 const std::string& name) {
  auto options = tight();
  options.relative_tolerance = 1e-12;
  options.absolute_tolerance = 1e-12;
  auto central = [&](double step) {
    std::vector<double> q(p.begin(), p.end());
    q[k] = p[k] + step;
    const auto plus = runtime::simulate(model, runtime::Inputs{}, q, grid, options);
    q[k] = p[k] - step;
    const auto minus = runtime::simulate(model, runtime::Inputs{}, q, grid, options);
    REQUIRE(plus.ok());
    REQUIRE(minus.ok());
    const auto a = column(plus.trajectory, name), b = column(minus.trajectory, name);
    std::vector<double> d(a.size());
    for (std::size_t r = 0; r < a.size(); ++r) d[r] = (a[r] - b[r]) / (2 * step);
    return d;
  };
  const auto d1 = central(h), d2 = central(2 * h);
  std::vector<double> d(d1.size());
  for (std::size_t r = 0; r < d.size(); ++r) d[r] = (4 * d1[r] - d2[r]) / 3;
  return d;
}

/// Largest |a_r - b_r| and largest |b_r| over the rows after the first (the
/// first row, at t0, is where both start equal by construction).
struct Deviation {
  double worst = 0;
  double scale = 0;
};
inline Deviation deviation_after_t0(const std::vector<double>& a, const std::vector<double>& b) {
  REQUIRE(a.size() == b.size());
  Deviation d;
  for (std::size_t r = 1; r < a.size(); ++r) {
    d.worst = std::max(d.worst, std::fabs(a[r] - b[r]));
    d.scale = std::max(d.scale, std::fabs(b[r]));
  }
  return d;
}

/// A model of tests/e2e/data compiled as `name` (every variable a column),
/// simulated from 0 to `stop` on `intervals` intervals (REQUIREs success):
/// its times, and any variable by name (a column, or an eliminated one).
struct DataRun {
  std::string name;
  std::vector<double> params;
  runtime::SimulationResult result;
  std::vector<double> times() const { return result.trajectory.times(); }
  std::vector<double> operator()(const std::string& v) const {
    return variable(name, result.trajectory, params, v);
  }
};

/// `cls` of `file`; against the MSL of ../shared when `msl` (nullopt:
/// skipped without it).
inline std::optional<DataRun> run_data_model(const std::string& name, const std::string& file,
                                             const std::string& cls, double stop, std::size_t intervals,
                                             bool msl = false) {
  const ModelSpec spec{{kData + file, cls, {}, true}, {}, true};
  auto model = msl ? msl_compiled_model(name, spec) : compiled_model(name, spec);
  if (!model) return std::nullopt;
  DataRun out{name, model->info().default_parameters(), {}};
  out.result = runtime::simulate(*model, {}, out.params, runtime::OutputGrid::uniform(0, stop, intervals), tight());
  INFO(out.result.message);
  REQUIRE(out.result.ok());
  return out;
}

}  // namespace mo::e2e
