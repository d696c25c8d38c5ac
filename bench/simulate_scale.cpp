// Simulation benchmark: a chain of N mass-spring-damper units (2N states, a
// step force on the last mass; tests/codegen/models.hpp) simulated over 1 s
// at rtol 1e-6 on dense LU and on KLU (runtime/src/cvode_jacobian.hpp), the
// model compiled once (cached). Prints one line per N:
//   N states steps dense_s klu_s max_abs_difference
// Usage: simulate_scale [N ...]   (default: 50 200 1000 2000)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "codegen/models.hpp"
#include "mo/codegen/generate.hpp"
#include "mo/codegen/shared_object.hpp"
#include "mo/runtime/simulate.hpp"

namespace {

using namespace mo;

runtime::SimulationResult run(runtime::Model& model, runtime::LinearSolverChoice choice, double& seconds) {
  runtime::SimulationOptions o;
  o.linear_solver = choice;
  runtime::Inputs inputs;
  inputs.add(runtime::constant_input(1.0));
  const auto start = std::chrono::steady_clock::now();
  runtime::SimulationResult r =
      runtime::simulate(model, inputs, model.info().default_parameters(), runtime::OutputGrid::uniform(0, 1, 100), o);
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

void measure(int n) {
  symbolic::OdeModel ode = codegen::test::spring_chain(n);
  const codegen::GeneratedSources src = codegen::generate_cpp(ode);
  codegen::CompilerOptions o = codegen::runtime_compiler_options();
  o.cache_dir = (std::filesystem::temp_directory_path() / "mocompile-bench-simulate").string();
  const codegen::CompiledModel so = codegen::compile_shared_object(src, o);
  auto model = codegen::LoadedModel(so.library, src.factory_symbol).create();
  double dense_s = 0, klu_s = 0;
  const auto dense = run(*model, runtime::LinearSolverChoice::dense, dense_s);
  const auto klu = run(*model, runtime::LinearSolverChoice::sparse, klu_s);
  double diff = 0;
  const auto a = dense.trajectory.column("tip"), b = klu.trajectory.column("tip");
  for (std::size_t k = 0; k < a.size() && k < b.size(); ++k) diff = std::max(diff, std::abs(a[k] - b[k]));
  std::printf("%d %zu %ld %.3f %.3f %.2g%s\n", n, ode.states.size(), klu.statistics.steps, dense_s, klu_s, diff,
              dense.ok() && klu.ok() ? "" : " (failed)");
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::printf("N states steps dense_s klu_s max_abs_difference\n");
  if (argc == 1)
    for (int n : {50, 200, 1000, 2000}) measure(n);
  for (int i = 1; i < argc; ++i) measure(std::atoi(argv[i]));
}
