// Simulation benchmark: the cart-pendulum (CartPendulumODE.mo, F = 3 sin 2πt)
// from its .mo file, 10 s at rtol 1e-6 and 1e-10, without sensitivities, with
// the compiler's sensitivity states for all five parameters, and with CVODES'
// sensitivity module (analytic and difference-quotient right-hand sides).
// Prints one row per run (median wall time of `repeats` runs):
//   case rtol states steps rhs_calls sens_rhs_calls jac_evals wall_ms
// Usage: simulate_cart_pendulum [repeats]   (default 5)
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <vector>

#include "mo/codegen/generate.hpp"
#include "mo/codegen/shared_object.hpp"
#include "mo/runtime/simulate.hpp"
#include "pipeline.hpp"

using namespace mo;

namespace {

std::unique_ptr<runtime::Model> build(const std::vector<std::string>& sensitivities, const std::string& name) {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  tools::ModelSource src{std::string(MO_SOURCE_DIR) + "/modelica/CartPendulum/CartPendulumODE.mo",
                         "CartPendulumODE", {}, true};
  auto flat = tools::load_flat_model(src, sources, diags);
  std::optional<symbolic::OdeModel> ode;
  if (flat) ode = tools::lower_model(*flat, diags);
  if (!ode) {
    diags.print(std::cerr);
    std::exit(1);
  }
  if (auto error = tools::add_named_sensitivities(*ode, sensitivities); !error.empty()) {
    std::cerr << error << "\n";
    std::exit(1);
  }
  codegen::CodegenOptions co;
  co.name = name;
  const auto generated = codegen::generate_cpp(*ode, co);
  codegen::CompilerOptions o = codegen::runtime_compiler_options();
  o.cache_dir = (std::filesystem::temp_directory_path() / "mocompile-bench-cache").string();
  o.jobs = 2;
  const auto so = codegen::compile_shared_object(generated, o);
  return codegen::LoadedModel(so.library, generated.factory_symbol).create();
}

void measure(const char* label, runtime::Model& model, double rtol, runtime::SensitivityMethod method,
             const std::vector<std::size_t>& parameters, int repeats) {
  runtime::SimulationOptions opt;
  opt.relative_tolerance = rtol;
  opt.absolute_tolerance = rtol * 1e-2;
  opt.sensitivities.method = method;
  opt.sensitivities.parameters = parameters;
  std::vector<double> wall;
  runtime::SimulationResult r;
  for (int i = 0; i < repeats; ++i) {
    runtime::Inputs inputs;
    inputs.add(runtime::sine_input(3.0, 1.0));
    r = runtime::simulate(model, inputs, model.info().default_parameters(),
                          runtime::OutputGrid::uniform(0, 10, 1000), opt);
    if (!r.ok()) {
      std::cerr << label << ": " << r.message << "\n";
      std::exit(1);
    }
    wall.push_back(r.statistics.wall_time_seconds);
  }
  std::sort(wall.begin(), wall.end());
  const auto& s = r.statistics;
  std::printf("%-18s %-6.0e %6zu %6ld %9ld %14ld %9ld %8.2f\n", label, rtol, model.info().states.size(), s.steps,
              s.rhs_evaluations, s.sensitivity_rhs_evaluations, s.jacobian_evaluations,
              1e3 * wall[wall.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const std::vector<std::string> names{"m1", "d1", "m2", "d2", "l"};
  auto plain = build({}, "bench_cart_pendulum");
  auto augmented = build(names, "bench_cart_pendulum_sens");
  std::vector<std::size_t> J;
  for (const auto& n : names) J.push_back(*plain->info().parameter_index(n));
  std::printf("%-18s %-6s %6s %6s %9s %14s %9s %8s\n", "case", "rtol", "states", "steps", "rhs_calls",
              "sens_rhs_calls", "jac_evals", "wall_ms");
  for (double rtol : {1e-6, 1e-10}) {
    measure("plain", *plain, rtol, runtime::SensitivityMethod::none, {}, repeats);
    measure("sens_states", *augmented, rtol, runtime::SensitivityMethod::model_states, {}, repeats);
    measure("cvodes_analytic", *plain, rtol, runtime::SensitivityMethod::cvodes_analytic, J, repeats);
    if (rtol > 1e-9)  // difference quotients cannot reach rtol 1e-10 (see simulate.hpp)
      measure("cvodes_difference", *plain, rtol, runtime::SensitivityMethod::cvodes_difference, J, repeats);
  }
}
