// Benchmark: the cart-pendulum T-optimal input design for m2 (docs/cart-pendulum.md,
// Step 3) with n_e = 100 and n_cp = 1 and 3. Prints NLP size, iterations, timings,
// the Fisher information in collocation and on replay, and the replay's bound violation.
// Usage: optim_cart_pendulum [n_cp ...] [--log DIR] [--ipopt NAME VALUE ...]
//        [--criterion A|T|D|E] [--ne N] [--d2] [--progress] [--sparse]
#include "fixtures.hpp"
#include "sparse_sensitivities.hpp"
#include "mo/runtime/design.hpp"

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <string>
#include <vector>

using namespace mo::runtime;

namespace {

InputDesignProblem design_problem(int n_cp) {
  InputDesignProblem d;
  OptimalControlProblem& p = d.ocp;
  p.t0 = 0.0, p.tf = 5.0;
  p.controls = {FreeControl{0, {-5.0, 5.0}, sine_input(2.0, 1.0, 0.0, 1.5), {}}};
  p.state_bounds = {{0, {0.0, 0.5}}, {1, {-0.5, 0.5}}, {2, {0.0, 0.5}}, {3, {-0.5, 0.5}}};
  p.final_state = {{0, {0.5, 0.5}}, {1, {0.0, 0.0}}, {2, {0.0, 0.0}}, {3, {0.0, 0.0}}};
  p.collocation.n_e = 100, p.collocation.n_cp = n_cp;
  p.solver.max_iterations = 1000;
  p.solver.tolerance = 1e-6;
  p.solver.acceptable_tolerance = 1e-2;  // L-BFGS crawls near the optimum
  p.solver.acceptable_objective_change = 1e-6;
  d.parameters = {2};  // m2
  d.measurements = {{0, 1}, {0.01, 0.01}, MeasurementDesign::uniform_times(0.0, 5.0, 100)};
  d.criterion = DesignCriterion::T;
  return d;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> points;
  std::string log_dir;
  std::map<std::string, std::string> extra;  // --ipopt NAME VALUE
  char criterion = 'T';                       // --criterion A|T|D|E
  int n_e = 100;                              // --ne N (also the number of samples)
  bool with_d2 = false, progress = false;     // --d2: design for (m2, d2); --progress
  bool sparse = false;  // --sparse: the true ∂f/∂x pattern instead of the fixture's dense one
  for (int k = 1; k < argc; ++k) {
    std::string arg = argv[k];
    if (arg == "--log" && k + 1 < argc) log_dir = argv[++k];
    else if (arg == "--ipopt" && k + 2 < argc) extra[argv[k + 1]] = argv[k + 2], k += 2;
    else if (arg == "--criterion" && k + 1 < argc) criterion = argv[++k][0];
    else if (arg == "--ne" && k + 1 < argc) n_e = std::atoi(argv[++k]);
    else if (arg == "--d2") with_d2 = true;
    else if (arg == "--progress") progress = true;
    else if (arg == "--sparse") sparse = true;
    else points.push_back(std::atoi(arg.c_str()));
  }
  if (points.empty()) points = {1, 3};
  std::printf("%-5s %7s %7s %8s %6s %9s %9s %9s %10s %10s %9s\n", "n_cp", "n", "m", "nnz_jac",
              "iter", "build_s", "solve_s", "eval_s", "info_coll", "info_resim", "violation");
  for (int n_cp : points) {
    fixtures::WithSensitivities<fixtures::CartPendulum> dense_plant;
    bench::SparseSensitivities<fixtures::CartPendulum> sparse_plant;
    const Model& plant = sparse ? static_cast<const Model&>(sparse_plant) : dense_plant;
    InputDesignProblem problem = design_problem(n_cp);
    problem.ocp.solver.ipopt_options = extra;
    problem.ocp.collocation.n_e = n_e;
    problem.measurements.times = MeasurementDesign::uniform_times(0.0, 5.0, std::size_t(n_e));
    if (with_d2) problem.parameters = {2, 3};
    if (progress) problem.ocp.solver.progress = print_progress(std::cout);
    problem.criterion = criterion == 'A'   ? DesignCriterion::A
                        : criterion == 'D' ? DesignCriterion::D
                        : criterion == 'E' ? DesignCriterion::E
                                           : DesignCriterion::T;
    if (!log_dir.empty()) problem.ocp.solver.log_file = log_dir + "/ipopt_ncp" + std::to_string(n_cp) + ".log";
    InputDesignResult r = design_input(plant, problem);
    const OptimizationResult& o = r.optimization;
    std::printf("%-5d %7d %7d %8d %6d %9.2f %9.2f %9.2f %10.2f %10.2f %9.4f  %s\n", n_cp,
                o.size.variables, o.size.constraints, o.size.jacobian_nonzeros, o.iterations,
                o.timings.nlp_build, o.timings.solve, o.timings.function_evaluations,
                r.information_collocation, r.information_resimulated,
                o.check.max_bound_violation, std::string(to_string(o.status)).c_str());
    for (const std::string& retry : o.retries) std::printf("      retry: %s\n", retry.c_str());
    if (!o.check.message.empty()) std::printf("      replay: %s\n", o.check.message.c_str());
  }
  return 0;
}
