// Benchmark: cart-pendulum input designs (docs/cart-pendulum.md, Step 3) on the
// model generated from modelica/CartPendulum/CartPendulumODE.mo, one start each:
//   T design for m2, n_e = 100, Radau n_cp = 3 and 1, 100 samples;
//   D and E designs for m1, d1, m2, d2, l with n_e = 50 (50 samples).
// Prints NLP size, iterations, timings, the information in collocation and on
// replay, and the replay's bound violation (docs/benchmarks.md).
// M20 (only when named): the T3 design from its guess and 19 random starts on
// every core (studies/multistart.hpp), its wall time against one start's.
// Usage: optim_cart_pendulum [CASE ...] [--lbfgs] [--progress] [--log DIR]
//        [--no-init-traj] [--no-nominal-traj] [--ipopt NAME VALUE ...]
//        CASE: T3 T1 D5 E5 M20 (default: the first four)
#include <chrono>
#include <functional>
#include <optional>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "mo/codegen/generate.hpp"
#include "mo/codegen/shared_object.hpp"
#include "mo/runtime/design.hpp"
#include "multistart.hpp"
#include "parallel_runner.hpp"
#include "pipeline.hpp"

using namespace mo;
using namespace mo::runtime;

namespace {

std::unique_ptr<Model> build(const std::vector<std::string>& sensitivities, const std::string& name) {
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

struct Case {
  std::string label;
  DesignCriterion criterion;
  std::vector<std::string> parameters;
  int n_e, n_cp;
};

// The paper's problem (12): rest to x = 0.5 m in 5 s within the state bounds.
InputDesignProblem design_problem(const Model& m, const Case& c) {
  const ModelInfo& info = m.info();
  auto state = [&](const char* n) { return *info.state_index(n); };
  InputDesignProblem d;
  OptimalControlProblem& p = d.ocp;
  p.t0 = 0.0, p.tf = 5.0;
  p.controls = {FreeControl{0, {-5.0, 5.0}, sine_input(2.0, 1.0, 0.0, 1.5), {}}};
  p.state_bounds = {{state("x"), {0.0, 0.5}}, {state("phi"), {-0.5, 0.5}},
                    {state("v"), {0.0, 0.5}}, {state("w"), {-0.5, 0.5}}};
  p.final_state = {{state("x"), {0.5, 0.5}}, {state("phi"), {0.0, 0.0}},
                   {state("v"), {0.0, 0.0}}, {state("w"), {0.0, 0.0}}};
  p.collocation.n_e = c.n_e, p.collocation.n_cp = c.n_cp;
  p.solver.max_iterations = 1000;
  p.solver.tolerance = 1e-6;
  for (const auto& name : c.parameters) d.parameters.push_back(*info.parameter_index(name));
  d.measurements = {{*info.output_index("y_x"), *info.output_index("y_phi")},
                    {0.01, 0.01},
                    MeasurementDesign::uniform_times(0.0, 5.0, std::size_t(c.n_e))};
  d.criterion = c.criterion;
  return d;
}

double wall_seconds(const std::function<void()>& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// M20: one start, then 20 (the guess and 19 random, seed 1) on every core.
void multistart_case(const Model& model, const InputDesignProblem& problem) {
  InputDesignResult one;
  const double single = wall_seconds([&] { one = design_input(model, problem); });
  tools::StudyOptions o;
  o.random_starts = 19;
  const auto starts = tools::design_starts(o, problem.ocp, model.info());
  tools::MultistartSettings settings;
  settings.jobs = tools::default_jobs();
  settings.output_dir = (std::filesystem::temp_directory_path() / "mocompile-bench-multistart").string();
  std::optional<tools::MultistartResult> m;
  const double all = wall_seconds([&] { m = tools::run_multistart(model, problem, starts, settings); });
  std::printf("M20: one start %.2f s (tr F %.6g); 20 starts on %u processes %.2f s = %.1f x one start "
              "(target < 10 x on 2 cores)\n",
              single, one.information_collocation, settings.jobs, all, all / single);
  if (!m) return;
  double sum = 0.0, seconds = 0.0;
  for (const auto& s : m->starts) sum += s.iterations, seconds += s.seconds;
  std::printf("M20: iterations: one start %d, the 20 starts %.1f on average (%.2f s per start)\n",
              one.optimization.iterations, sum / double(m->starts.size()), seconds / double(m->starts.size()));
  tools::print_multistart(std::cout, *m, "T", settings);
}

}  // namespace

int main(int argc, char** argv) {
  const std::map<std::string, Case> cases = {
      {"T3", {"T3", DesignCriterion::T, {"m2"}, 100, 3}},
      {"T1", {"T1", DesignCriterion::T, {"m2"}, 100, 1}},
      {"D5", {"D5", DesignCriterion::D, {"m1", "d1", "m2", "d2", "l"}, 50, 3}},
      {"E5", {"E5", DesignCriterion::E, {"m1", "d1", "m2", "d2", "l"}, 50, 3}},
  };
  std::vector<std::string> chosen;
  std::string log_dir;
  bool lbfgs = false, progress = false, init_traj = true, nominal_traj = true;
  std::map<std::string, std::string> extra;  // --ipopt NAME VALUE
  for (int k = 1; k < argc; ++k) {
    std::string arg = argv[k];
    if (arg == "--lbfgs") lbfgs = true;
    else if (arg == "--progress") progress = true;
    else if (arg == "--log" && k + 1 < argc) log_dir = argv[++k];
    else if (arg == "--no-init-traj") init_traj = false;
    else if (arg == "--no-nominal-traj") nominal_traj = false;
    else if (arg == "--ipopt" && k + 2 < argc) extra[argv[k + 1]] = argv[k + 2], k += 2;
    else if (cases.count(arg) || arg == "M20") chosen.push_back(arg);
    else {
      std::cerr << "usage: optim_cart_pendulum [T3|T1|D5|E5|M20 ...] [--lbfgs] [--progress] [--log DIR]"
                   " [--no-init-traj] [--no-nominal-traj] [--ipopt NAME VALUE ...]\n";
      return 2;
    }
  }
  if (chosen.empty()) chosen = {"T3", "T1", "D5", "E5"};
  std::unique_ptr<Model> m2 = build({"m2"}, "bench_cart_m2");
  std::unique_ptr<Model> all = build({"m1", "d1", "m2", "d2", "l"}, "bench_cart_all");
  std::printf("%-4s %4s %4s %7s %7s %8s %8s %6s %9s %9s %9s %12s %12s %9s\n", "case", "n_e",
              "n_cp", "n", "m", "nnz_jac", "nnz_hess", "iter", "build_s", "solve_s", "eval_s",
              "info_coll", "info_resim", "violation");
  for (const std::string& name : chosen) {
    const Case& c = cases.at(name == "M20" ? "T3" : name);
    const Model& model = c.parameters.size() == 1 ? *m2 : *all;
    InputDesignProblem problem = design_problem(model, c);
    problem.ocp.collocation.init_traj = init_traj;
    problem.ocp.collocation.nominal_traj = nominal_traj && init_traj;
    problem.ocp.solver.ipopt_options = extra;
    if (lbfgs) problem.ocp.solver.hessian = HessianMode::limited_memory;
    if (lbfgs) problem.ocp.solver.acceptable_tolerance = 1e-2;  // L-BFGS crawls near the optimum
    if (lbfgs) problem.ocp.solver.acceptable_objective_change = 1e-6;
    if (name == "M20") {  // the same settings, without progress or log
      multistart_case(model, problem);
      continue;
    }
    if (progress) problem.ocp.solver.progress = print_progress(std::cout);
    if (!log_dir.empty()) problem.ocp.solver.log_file = log_dir + "/ipopt_" + name + ".log";
    InputDesignResult r = design_input(model, problem);
    const OptimizationResult& o = r.optimization;
    std::printf("%-4s %4d %4d %7d %7d %8d %8d %6d %9.2f %9.2f %9.2f %12.6g %12.6g %9.2g  %s\n",
                name.c_str(), c.n_e, c.n_cp, o.size.variables, o.size.constraints,
                o.size.jacobian_nonzeros, o.size.hessian_nonzeros, o.iterations,
                o.timings.nlp_build, o.timings.solve, o.timings.function_evaluations,
                r.information_collocation, r.information_resimulated, o.check.max_bound_violation,
                std::string(to_string(o.status)).c_str());
    for (const std::string& retry : o.retries) std::printf("      retry: %s\n", retry.c_str());
    if (!o.check.message.empty()) std::printf("      replay: %s\n", o.check.message.c_str());
    std::fflush(stdout);
  }
  return 0;
}
