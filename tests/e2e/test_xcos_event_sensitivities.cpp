// Sensitivities through events on real Xcos models (issue 15): every model of
// ../shared/xcos-corpus/flat that has events, its states' sensitivities to two
// of its parameters (generated sensitivity states) against central
// differences of whole simulations (rtol 1e-10 for the sensitivities, 1e-11
// and a relative step of 1e-5 for the differences). Tolerance: 1e-3 of the largest |S| of the
// entry over the run (+ 1e-6), at output times more than 1e-3·tf from an event.
// Model inputs (driven by non-Modelica blocks in the diagram) follow the
// run's recorded input columns. Skipped when the corpus is absent; a model that does not lower or simulate
// yet (other work) is skipped with its reason.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "e2e/support.hpp"
#include "mo/runtime/input.hpp"
#include "mo/runtime/simulate.hpp"
#include "mo/symbolic/sensitivities.hpp"

using namespace mo;
using namespace mo::e2e;
namespace fs = std::filesystem;

namespace {

/// ../shared beside the checkout, else $MO_SHARED_DIR; empty if neither exists.
fs::path shared_dir() {
  const fs::path beside = fs::path(MO_SOURCE_DIR) / ".." / "shared";
  if (fs::exists(beside / "xcos-corpus")) return beside;
  if (const char* env = std::getenv("MO_SHARED_DIR"); env && fs::exists(fs::path(env) / "xcos-corpus"))
    return env;
  return {};
}

/// The lowered model, or nullopt (and the reason) if the pipeline rejects it.
std::optional<symbolic::OdeModel> lower(const fs::path& file, std::string& reason) {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  std::ostringstream printed;
  const tools::ModelSource source{file.string(), "", {}, true};
  auto flat = tools::load_flat_model(source, sources, diags);
  std::optional<symbolic::OdeModel> ode;
  if (flat) ode = tools::lower_model(*flat, diags);
  diags.print(printed);
  reason = printed.str().substr(0, 300);
  return ode;
}

/// The first two parameters with a nonzero value that get sensitivity states
/// (on a second lowering of `file`: the model itself stays as it is).
std::vector<std::string> two_parameters(const fs::path& file) {
  std::string reason;
  auto lowered = lower(file, reason);
  REQUIRE(lowered);
  symbolic::OdeModel& ode = *lowered;
  std::vector<std::size_t> candidates;
  for (std::size_t k = 0; k < ode.parameters.size(); ++k)
    if (ode.parameters[k].value != 0.0) candidates.push_back(k);
  symbolic::add_sensitivities(ode, candidates);
  std::vector<std::string> out;
  for (std::size_t k : candidates) {
    const bool has = std::any_of(ode.states.begin(), ode.states.end(), [&](const symbolic::OdeState& s) {
      return s.sensitivity && s.sensitivity->parameter == k;
    });
    if (has && out.size() < 2) out.push_back(ode.parameters[k].info.name);
  }
  return out;
}

/// Every model input driven by its column of the corpus's recorded run
/// (`ref/<name>.csv`, where Scilab's non-Modelica blocks wrote it), as the
/// corpus comparison drives them; `reason` says which input is missing.
std::optional<runtime::Inputs> recorded_inputs(const runtime::ModelInfo& info, const fs::path& csv,
                                               std::string& reason) {
  if (info.inputs.empty()) return runtime::Inputs{};
  auto table = std::make_shared<const runtime::InputTable>(runtime::read_input_csv(csv.string()));
  runtime::Inputs inputs;
  for (const auto& u : info.inputs) {
    if (std::find(table->names.begin(), table->names.end(), u.name) == table->names.end()) {
      reason = "input " + u.name + " is not recorded in " + csv.filename().string();
      return std::nullopt;
    }
    inputs.add(runtime::table_input(table, u.name));
  }
  return inputs;
}

/// Models whose sensitivities through events are known to fail, with why
/// (docs/events.md, "Limits"); the test fails if one of them passes.
const std::map<std::string, std::string> kKnownFailures{};

double final_time(const fs::path& json_file) {
  std::ifstream in(json_file);
  return nlohmann::json::parse(in)["tf"].get<double>();
}

}  // namespace

TEST_CASE("Xcos corpus models with events: sensitivities through events = central differences",
          "[events][sensitivities][xcos]") {
  const fs::path shared = shared_dir();
  if (shared.empty()) {
    WARN("SKIPPED: no ../shared/xcos-corpus beside the checkout and no MO_SHARED_DIR");
    return;
  }
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(shared / "xcos-corpus" / "flat"))
    if (entry.path().extension() == ".mo" && entry.path().stem().string().find("_hier") == std::string::npos)
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  int checked = 0;
  for (const fs::path& file : files) {
    const std::string name = file.stem().string();
    std::string reason;
    auto ode = lower(file, reason);
    if (!ode) {
      WARN("SKIPPED " << name << ": does not lower yet: " << reason);
      continue;
    }
    if (ode->whens.empty() && ode->zero_crossings.empty()) continue;  // no events
    const auto params = two_parameters(file);
    if (params.empty()) {
      WARN("SKIPPED " << name << ": no parameter with a nonzero value reaches a state");
      continue;
    }
    const double tf = final_time(shared / "xcos-corpus" / "ref" / (name + ".json"));
    const auto grid = runtime::OutputGrid::uniform(0, tf, 50);
    const std::string id = "e2e_xcos_ev_" + name;
    const tools::ModelSource source{file.string(), "", {}, true};
    auto plain = compiled_model(id, ModelSpec{source, {}});
    auto augmented = compiled_model(id + "_sens", ModelSpec{source, params});
    runtime::SimulationOptions o;
    o.relative_tolerance = 1e-10;
    o.absolute_tolerance = 1e-12;
    const auto p = plain->info().default_parameters();
    std::string missing;
    const auto inputs = recorded_inputs(plain->info(), shared / "xcos-corpus" / "ref" / (name + ".csv"), missing);
    if (!inputs) {
      WARN("SKIPPED " << name << ": " << missing);
      continue;
    }
    const auto nominal = runtime::simulate(*plain, *inputs, p, grid, o);
    if (!nominal.ok()) {
      WARN("SKIPPED " << name << ": does not simulate yet: " << nominal.message);
      continue;
    }
    auto os = o;
    os.sensitivities.method = runtime::SensitivityMethod::model_states;
    for (const auto& q : params) os.sensitivities.parameters.push_back(parameter(augmented->info(), q));
    const auto sens = runtime::simulate(*augmented, *inputs, augmented->info().default_parameters(), grid, os);
    INFO(name << ": " << sens.message);
    if (const auto known = kKnownFailures.find(name); known != kKnownFailures.end()) {
      CHECK_FALSE(sens.ok());  // fixed: take it off the list
      WARN("KNOWN FAILURE " << name << ": " << sens.message << " (" << known->second << ")");
      continue;
    }
    REQUIRE(sens.ok());
    const std::size_t nb = plain->info().states.size();
    double worst = 0;
    for (std::size_t j = 0; j < params.size(); ++j) {
      const std::size_t k = parameter(plain->info(), params[j]);
      const double h = 1e-5 * std::fabs(p[k]);  // p[k] != 0 (two_parameters)
      auto q = p;
      auto reference = o;  // tighter: the quotient divides the error by h
      reference.relative_tolerance = 1e-11;
      reference.absolute_tolerance = 1e-13;
      q[k] = p[k] + h;
      const auto plus = runtime::simulate(*plain, *inputs, q, grid, reference);
      q[k] = p[k] - h;
      const auto minus = runtime::simulate(*plain, *inputs, q, grid, reference);
      REQUIRE(plus.ok());
      REQUIRE(minus.ok());
      for (std::size_t i = 0; i < nb; ++i) {
        // The quotient's own noise, about rtol·|x|/h, is the floor of the
        // scale: a sensitivity that is exactly 0 (a prescribed motion) must
        // not fail on the integrator's rounding in the two runs.
        double x_max = 0;
        for (std::size_t r = 0; r < grid.times.size(); ++r) x_max = std::max(x_max, std::fabs(nominal.trajectory.at(r, i)));
        double scale = std::max(1e-6, 10 * reference.relative_tolerance * x_max / h);
        std::vector<double> fd(grid.times.size());
        for (std::size_t r = 0; r < grid.times.size(); ++r) {
          fd[r] = (plus.trajectory.at(r, i) - minus.trajectory.at(r, i)) / (2 * h);
          scale = std::max(scale, std::fabs(fd[r]) + 1e-6);
        }
        for (std::size_t r = 0; r < grid.times.size(); ++r) {
          const double t = grid.times[r];
          if (std::any_of(nominal.event_times.begin(), nominal.event_times.end(),
                          [&](double te) { return std::fabs(te - t) < 1e-3 * tf; }))
            continue;
          const double s = sens.state_sensitivities[r](static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
          const double e = std::fabs(s - fd[r]) / scale;
          if (e > worst) worst = e;
          if (e > 1e-3)
            FAIL_CHECK(name << ": d(" << plain->info().states[i].name << ")/d(" << params[j] << ") at t = " << t
                            << ": " << s << " vs central difference " << fd[r]);
        }
      }
    }
    ++checked;
    WARN(name << ": " << nominal.event_times.size() << " events, parameters " << params[0]
              << (params.size() > 1 ? ", " + params[1] : std::string()) << ": worst relative difference " << worst);
  }
  WARN(checked << " corpus models with events checked");
}
