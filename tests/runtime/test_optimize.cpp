// Optimal control by collocation: the minimum-energy rest-to-rest move of a
// double integrator, whose optimum is known in closed form.
#include "fixtures.hpp"
#include "mo/runtime/optimize.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace mo::runtime;

namespace {

// Move by d in time T with minimal ∫u² dt; rest at both ends.
OptimalControlProblem rest_to_rest(CollocationScheme scheme, int n_e, int n_cp, double d,
                                   double T) {
  OptimalControlProblem p;
  p.t0 = 0.0, p.tf = T;
  p.controls = {FreeControl{0, {-100.0, 100.0}, nullptr, {}}};
  p.lagrange = {LagrangeTerm{0, 1.0}};
  p.final_state = {FinalStateConstraint{0, {d, d}}, FinalStateConstraint{1, {0.0, 0.0}}};
  p.collocation.n_e = n_e, p.collocation.n_cp = n_cp, p.collocation.scheme = scheme;
  return p;
}

/// The double integrator, declared to read its input in the initial system.
class StartReadsInput final : public Model {
public:
  StartReadsInput() : info_(inner_.info()) { info_.input_in_initial = {true}; }
  const ModelInfo& info() const override { return info_; }
  std::unique_ptr<Model> clone() const override { return std::make_unique<StartReadsInput>(); }
  using Model::initial_state;
  void initial_state(double t0, std::span<const double> u0, std::span<const double> p,
                     std::span<double> x0) override {
    inner_.initial_state(t0, u0, p, x0);
  }
  void rhs(double t, std::span<const double> x, std::span<const double> u, std::span<const double> p,
           std::span<double> xdot) override {
    inner_.rhs(t, x, u, p, xdot);
  }
  void outputs(double t, std::span<const double> x, std::span<const double> u, std::span<const double> p,
               std::span<double> y) override {
    inner_.outputs(t, x, u, p, y);
  }
  const Sparsity& jacobian_sparsity(Jacobian block) const override { return inner_.jacobian_sparsity(block); }
  void jacobian_values(Jacobian block, double t, std::span<const double> x, std::span<const double> u,
                       std::span<const double> p, std::span<double> values) override {
    inner_.jacobian_values(block, t, x, u, p, values);
  }

private:
  fixtures::DoubleIntegrator inner_;
  ModelInfo info_;
};

}  // namespace

TEST_CASE("double integrator: minimum energy rest-to-rest matches the analytic optimum",
          "[optimize]") {
  const double d = 1.0, T = 2.0;
  const int n_e = 20;
  const double h = T / n_e;
  // Continuous optimum 12 d²/T³; with one constant u per element it is
  // 12 d² / (T³ − h² T) (the midpoint variance of the grid replaces T³/12).
  const double continuous = 12.0 * d * d / (T * T * T);
  const double piecewise = 12.0 * d * d / (T * T * T - h * h * T);
  for (auto scheme : {CollocationScheme::radau, CollocationScheme::gauss})
    for (int n_cp : {2, 3}) {
      CAPTURE(int(scheme), n_cp);
      fixtures::DoubleIntegrator model;
      OptimizationResult r = solve(model, rest_to_rest(scheme, n_e, n_cp, d, T));
      INFO(r.message);
      REQUIRE(r.ok());
      CHECK(r.objective == Approx(piecewise).epsilon(1e-7));
      CHECK(r.objective == Approx(continuous).epsilon(0.01));
      CHECK(r.size.hessian_nonzeros > 0);  // exact Hessian from the model
      for (int i = 0; i < n_e; ++i) {      // u(t) = 6 d/T² (1 − 2t/T) at element midpoints
        double mid = (i + 0.5) * h;
        double analytic = 6.0 * d / (T * T) * (1.0 - 2.0 * mid / T);
        CHECK(r.control_values[0][std::size_t(i)] ==
              Approx(analytic * (T * T) / (T * T - h * h)).margin(1e-6));
      }
      INFO(r.check.message);
      CHECK(r.check.performed);
      CHECK(r.check.max_state_difference < 1e-6);  // exact for piecewise-constant u
      CHECK(r.check.max_bound_violation < 1e-6);
    }
}

TEST_CASE("double integrator: limited-memory Hessian reaches the same optimum", "[optimize]") {
  fixtures::DoubleIntegrator model;
  OptimalControlProblem p = rest_to_rest(CollocationScheme::radau, 10, 3, 1.0, 1.0);
  p.solver.hessian = HessianMode::limited_memory;
  std::ostringstream log;
  p.solver.progress = print_progress(log);
  OptimizationResult r = solve(model, p);
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(r.size.hessian_nonzeros == 0);
  CHECK(r.objective == Approx(12.0 / (1.0 - 0.01)).epsilon(1e-6));
  const std::string lines = log.str();
  CHECK(std::count(lines.begin(), lines.end(), '\n') == r.iterations + 1);
}

TEST_CASE("double integrator: the optimum converges at second order as n_e grows", "[optimize]") {
  // Piecewise-constant controls: J(n_e) − J* = 12 h² / (1 − h²) with J* = 12,
  // so halving the element length divides the error by about 4.
  fixtures::DoubleIntegrator model;
  std::vector<double> error;
  for (int n_e : {5, 10, 20, 40}) {
    OptimizationResult r = solve(model, rest_to_rest(CollocationScheme::radau, n_e, 2, 1.0, 1.0));
    REQUIRE(r.ok());
    error.push_back(r.objective - 12.0);
  }
  for (std::size_t k = 1; k < error.size(); ++k) {
    INFO("n_e step " << k << ": errors " << error[k - 1] << " -> " << error[k]);
    CHECK(error[k - 1] / error[k] == Approx(4.0).epsilon(0.05));
  }
}

TEST_CASE("optimisation reports an infeasible problem with a typed status", "[optimize]") {
  fixtures::DoubleIntegrator model;
  OptimalControlProblem p = rest_to_rest(CollocationScheme::radau, 10, 2, 1.0, 1.0);
  p.controls[0].bounds = {-1.0, 1.0};  // a unit move in 1 s needs |u| ≥ 4
  p.solver.max_iterations = 200;
  OptimizationResult r = solve(model, p);
  CHECK_FALSE(r.ok());
  CHECK((r.status == OptimizationStatus::infeasible ||
         r.status == OptimizationStatus::restoration_failure));
  CHECK(r.trajectories.rows() > 0);  // the last iterate is still returned
}

TEST_CASE("an exact Hessian is refused when the model has none", "[optimize]") {
  fixtures::WithSensitivities<fixtures::LinearDecay> model;  // no Hessians
  OptimalControlProblem p;
  p.controls = {FreeControl{0, {-1.0, 1.0}, nullptr, {}}};
  p.lagrange = {LagrangeTerm{0, 1.0}};
  p.collocation.n_e = 5;
  p.solver.hessian = HessianMode::exact;
  OptimizationResult r = solve(model, p);
  CHECK(r.status == OptimizationStatus::invalid_problem);
  p.solver.hessian = HessianMode::automatic;  // falls back to L-BFGS
  r = solve(model, p);
  INFO(r.message);
  CHECK(r.ok());
  CHECK(r.size.hessian_nonzeros == 0);
}

TEST_CASE("optimisation rejects an inconsistent problem", "[optimize]") {
  fixtures::DoubleIntegrator model;
  OptimalControlProblem p = rest_to_rest(CollocationScheme::radau, 10, 2, 1.0, 1.0);
  p.controls[0].blocking_factors = {3, 3};  // sums to 6, n_e is 10
  OptimizationResult r = solve(model, p);
  CHECK(r.status == OptimizationStatus::invalid_problem);
  CHECK(r.message.find("blocking factors") != std::string::npos);
  p = rest_to_rest(CollocationScheme::radau, 10, 2, 1.0, 1.0);
  p.controls.clear();
  r = solve(model, p);
  CHECK(r.status == OptimizationStatus::invalid_problem);
  CHECK(r.message.find("neither a control nor fixed") != std::string::npos);
  // x0 = x0(p, u(t0)) has no derivative with respect to a control.
  StartReadsInput reads;
  r = solve(reads, rest_to_rest(CollocationScheme::radau, 10, 2, 1.0, 1.0));
  CHECK(r.status == OptimizationStatus::invalid_problem);
  CHECK(r.message.find("the initial system reads input 'u'") != std::string::npos);
  p = rest_to_rest(CollocationScheme::radau, 10, 2, 1.0, 1.0);
  p.controls.clear();
  p.fixed_inputs = {{0, std::shared_ptr<const InputSignal>(constant_input(0.0))}};
  p.final_state.clear();
  r = solve(reads, p);  // a given signal is read at t0: solved
  INFO(r.message);
  CHECK(r.ok());
}

TEST_CASE("optimisation writes trajectories, re-simulation and summary", "[optimize]") {
  fixtures::DoubleIntegrator model;
  OptimalControlProblem p = rest_to_rest(CollocationScheme::radau, 10, 3, 1.0, 1.0);
  p.controls[0].blocking_factors = {5, 5};  // bang-bang-like: two control values
  auto dir = std::filesystem::temp_directory_path() / "mo_optimize_test";
  std::filesystem::create_directories(dir);
  p.solver.log_file = (dir / "ipopt.log").string();
  OptimizationResult r = solve(model, p);
  REQUIRE(r.ok());
  CHECK(r.control_values[0][0] == Approx(4.0).epsilon(1e-6));  // u = ±4 for 1/2 s each
  CHECK(r.control_values[0][9] == Approx(-4.0).epsilon(1e-6));
  CHECK(r.objective == Approx(16.0).epsilon(1e-6));
  write_optimization_result(dir.string(), r, model.info());
  std::ifstream summary(dir / "summary.json");
  std::string text((std::istreambuf_iterator<char>(summary)), {});
  CHECK(text.find("\"status\": \"success\"") != std::string::npos);
  CHECK(std::filesystem::file_size(dir / "trajectories.csv") > 100);
  CHECK(std::filesystem::file_size(dir / "resimulated.csv") > 100);
  CHECK(std::filesystem::file_size(dir / "ipopt.log") > 100);
}

TEST_CASE("free parameter, fixed input and a point constraint", "[optimize]") {
  // a' = -k a + u with u = 0 fixed and a(0) = a0 free: a(1) = 0.5 needs a0 = 0.5 e^k.
  fixtures::LinearDecay model;
  OptimalControlProblem p;
  p.t0 = 0.0, p.tf = 2.0;
  p.fixed_inputs = {{0, std::shared_ptr<const InputSignal>(constant_input(0.0))}};
  p.free_parameters = {FreeParameter{1, {0.0, 10.0}, 1.0}};
  p.point_constraints = {PointConstraint{0, 1.0, {0.5, 0.5}}};
  p.mayer = {MayerTerm{1, 1.0}};  // k·b(tf) = k ∫a dt: fixed by the constraint too
  p.collocation.n_e = 10, p.collocation.n_cp = 3;
  OptimizationResult r = solve(model, p);
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(r.parameters[1] == Approx(0.5 * std::exp(2.0)).epsilon(1e-5));
  CHECK(r.check.max_state_difference < 1e-4);
}
