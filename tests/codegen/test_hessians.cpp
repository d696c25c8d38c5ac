// Exact Hessians of generated models: ∇²_z(λᵀf) and ∇²_z(μᵀh) against
// central differences of the generated Jacobians and the hand-written
// cart-pendulum fixture; through linear and nonlinear blocks and sensitivity
// states; and an estimation with Ipopt's exact Hessian against limited memory.
#include <catch2/catch.hpp>

#include <chrono>
#include <iostream>
#include <random>

#include "codegen/hessian_check.hpp"
#include "codegen/models.hpp"
#include "codegen/support.hpp"
#include "mo/runtime/estimate.hpp"
#include "mo/runtime/simulate.hpp"
#include "mo/symbolic/sensitivities.hpp"
#include "runtime/fixtures.hpp"

using namespace mo;
using namespace mo::codegen::test;
using runtime::Hessian;

namespace {

struct Point {
  double t;
  std::vector<double> x, u, p;
};

Point random_cart_point(std::mt19937& rng, std::size_t nx = 4) {
  std::uniform_real_distribution<double> unit(-1, 1), scale(0.8, 1.2);
  Point pt{unit(rng), {unit(rng), 3 * unit(rng), unit(rng), 2 * unit(rng)}, {5 * unit(rng)},
           {2 * scale(rng), 15 * scale(rng), scale(rng), 0.5 * scale(rng), 0.5 * scale(rng)}};
  while (pt.x.size() < nx) pt.x.push_back(unit(rng));
  return pt;
}

std::vector<double> random_weights(std::mt19937& rng, std::size_t n) {
  std::uniform_real_distribution<double> unit(-1, 1);
  std::vector<double> w(n);
  for (double& v : w) v = unit(rng);
  return w;
}

symbolic::OdeModel cart_pendulum_m2_sensitivities() {
  symbolic::OdeModel m = cart_pendulum();
  symbolic::add_sensitivities(m, std::vector<std::size_t>{2});  // m2
  return m;
}

}  // namespace

TEST_CASE("cart pendulum: generated Hessians match finite differences of the Jacobians", "[hessian]") {
  auto model = compiled("cart_pendulum", cart_pendulum);
  REQUIRE(model->provides_hessian(Hessian::f));
  REQUIRE(model->provides_hessian(Hessian::h));
  std::mt19937 rng(11);
  for (int k = 0; k < 5; ++k) {
    const Point pt = random_cart_point(rng);
    CHECK(check_hessian(*model, Hessian::f, pt.t, pt.x, pt.u, pt.p, random_weights(rng, 4)) > 20);
    CHECK(check_hessian(*model, Hessian::h, pt.t, pt.x, pt.u, pt.p, random_weights(rng, 2)) == 0);
  }
  // Structure: the accelerations M(φ, m1, m2, l)⁻¹ b are nonlinear in M's
  // four arguments (10 pairs), bilinear between those and b's linear
  // arguments v, w, F, d1, d2 (20), and b holds w², d1·v and d2·w (3): 33 of
  // the 45 entries of a dense 9 × 9 triangle (x unused); h is linear: empty.
  const runtime::Sparsity& f = model->hessian_sparsity(Hessian::f);
  CHECK(f.col_start[1] == 0);
  CHECK(f.nnz() == 33);
  CHECK(model->hessian_sparsity(Hessian::h).nnz() == 0);
}

TEST_CASE("cart pendulum: generated Hessian equals the hand-written fixture's", "[hessian]") {
  auto model = compiled("cart_pendulum", cart_pendulum);
  runtime::fixtures::CartPendulum hand;
  REQUIRE(hand.info().parameters.size() == model->info().parameters.size());
  for (std::size_t j = 0; j < 5; ++j)
    REQUIRE(hand.info().parameters[j].name == model->info().parameters[j].name);
  std::mt19937 rng(12);
  for (int k = 0; k < 3; ++k) {
    const Point pt = random_cart_point(rng);
    const auto w = random_weights(rng, 4);
    const runtime::Sparsity& mine = model->hessian_sparsity(Hessian::f);
    const runtime::Sparsity& theirs = hand.hessian_sparsity(Hessian::f);
    std::vector<double> a(static_cast<std::size_t>(mine.nnz())), b(static_cast<std::size_t>(theirs.nnz()));
    model->hessian_values(Hessian::f, pt.t, pt.x, pt.u, pt.p, w, a);
    hand.hessian_values(Hessian::f, pt.t, pt.x, pt.u, pt.p, w, b);
    for (int c = 0; c < 10; ++c)
      for (int r = c; r < 10; ++r) {
        const int i = mine.find(r, c), j = theirs.find(r, c);
        if (i >= 0) CHECK(j >= 0);  // the fixture's pattern is a superset
        const double x = i < 0 ? 0.0 : a[static_cast<std::size_t>(i)];
        const double y = j < 0 ? 0.0 : b[static_cast<std::size_t>(j)];
        INFO("entry (" << r << ", " << c << ")");
        CHECK(close(x, y, 1e-5));
      }
  }
}

TEST_CASE("nonlinear block: generated Hessians match finite differences", "[hessian]") {
  auto model = compiled("cubic_root", cubic_root);
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> xs(-5, 5), ks(0.5, 2);
  for (int k = 0; k < 5; ++k) {
    const std::vector<double> x{xs(rng)}, p{ks(rng), 2.0};
    // z(x, k) from z³ + k z = x: second derivatives in (x, k); x0 not involved.
    CHECK(check_hessian(*model, Hessian::f, 0.0, x, {}, p, random_weights(rng, 1)) == 3);
    CHECK(check_hessian(*model, Hessian::h, 0.0, x, {}, p, random_weights(rng, 2)) == 3);
  }
  const runtime::Sparsity& f = model->hessian_sparsity(Hessian::f);
  CHECK(f.nnz() == 3);  // (x, x), (k, x), (k, k) in z = (x, k, x0)
}

TEST_CASE("cart pendulum with m2 sensitivities: Hessians of f and h", "[hessian]") {
  auto model = compiled("cart_pendulum_sens", cart_pendulum_m2_sensitivities);
  const std::size_t nx = model->info().states.size(), ny = model->info().outputs.size();
  REQUIRE(nx == 8);
  REQUIRE(ny > 2);  // output sensitivities
  std::mt19937 rng(14);
  for (int k = 0; k < 3; ++k) {
    const Point pt = random_cart_point(rng, nx);
    CHECK(check_hessian(*model, Hessian::f, pt.t, pt.x, pt.u, pt.p, random_weights(rng, nx), 1e-5) > 20);
    check_hessian(*model, Hessian::h, pt.t, pt.x, pt.u, pt.p, random_weights(rng, ny), 1e-5);
  }
  // The sensitivity equations der(s) = J(x)s + ∂f/∂p are linear in s: no
  // (s, s) entries in the pattern, only (s, z) with z in J's arguments.
  const std::size_t base = model->info().num_base_states();
  REQUIRE(base == 4);
  const runtime::Sparsity& f = model->hessian_sparsity(Hessian::f);
  int sensitivity_entries = 0;
  for (int c = static_cast<int>(base); c < static_cast<int>(nx); ++c)
    for (int r = c; r < static_cast<int>(nx); ++r) {
      INFO("entry (" << r << ", " << c << ")");
      CHECK(f.find(r, c) < 0);
    }
  for (int c = 0; c < f.cols; ++c)
    for (int r = static_cast<int>(base); r < static_cast<int>(nx); ++r)
      if (f.find(r, c) >= 0) ++sensitivity_entries;
  CHECK(sensitivity_entries > 0);
}

TEST_CASE("generated Hessian for wanted columns: their entries as the full evaluation, the rest skipped",
          "[hessian]") {
  auto model = compiled("cart_pendulum_sens", cart_pendulum_m2_sensitivities);
  const runtime::ModelInfo& info = model->info();
  const std::size_t nz = info.states.size() + info.inputs.size() + info.parameters.size();
  std::vector<std::uint8_t> xu(nz, 0), one_parameter(nz, 1);
  for (std::size_t c = 0; c < info.states.size() + info.inputs.size(); ++c) xu[c] = 1;  // a design's columns
  one_parameter[info.states.size() + info.inputs.size() + 1] = 0;                     // all but d1
  const runtime::Sparsity& sp = model->hessian_sparsity(Hessian::f);
  std::mt19937 rng(15);
  for (const auto& columns : {xu, one_parameter}) {
    const Point pt = random_cart_point(rng, info.states.size());
    const auto w = random_weights(rng, info.states.size());
    std::vector<double> all(static_cast<std::size_t>(sp.nnz())), some(all.size(), -1.0);
    model->hessian_values(Hessian::f, pt.t, pt.x, pt.u, pt.p, w, all);
    model->hessian_values_for(columns, Hessian::f, pt.t, pt.x, pt.u, pt.p, w, some);
    int skipped = 0;
    for (int c = 0; c < sp.cols; ++c)
      for (int k = sp.col_start[std::size_t(c)]; k < sp.col_start[std::size_t(c) + 1]; ++k) {
        const auto r = static_cast<std::size_t>(sp.row_index[std::size_t(k)]);
        INFO("entry (" << r << ", " << c << ")");
        if (columns[r] && columns[std::size_t(c)]) {
          // Coloured again over the wanted columns: the same values, summed in another order.
          CHECK(some[std::size_t(k)] == Approx(all[std::size_t(k)]).epsilon(1e-13).margin(1e-300));
        } else if (all[std::size_t(k)] != 0.0) {
          CHECK(some[std::size_t(k)] == 0.0);
          ++skipped;
        }
      }
    CHECK(skipped > 0);
  }
  // The model remembers the products of the last columns: asking for all again gives all.
  const Point pt = random_cart_point(rng, info.states.size());
  const auto w = random_weights(rng, info.states.size());
  std::vector<double> all(static_cast<std::size_t>(sp.nnz())), again(all.size());
  model->hessian_values(Hessian::f, pt.t, pt.x, pt.u, pt.p, w, all);
  model->hessian_values_for(xu, Hessian::f, pt.t, pt.x, pt.u, pt.p, w, again);
  model->hessian_values_for({}, Hessian::f, pt.t, pt.x, pt.u, pt.p, w, again);
  CHECK(again == all);
}

namespace {

runtime::EstimationProblem m2_estimation(runtime::Model& model, runtime::HessianMode mode,
                                         double noise) {
  runtime::Inputs inputs;
  inputs.add(runtime::sine_input(3.0, 1.0));
  std::vector<double> grid{0.0};
  runtime::EstimationExperiment ex;
  ex.inputs = {{0, std::shared_ptr<const runtime::InputSignal>(runtime::sine_input(3.0, 1.0))}};
  for (int k = 1; k <= 200; ++k) ex.data.times.push_back(0.01 * k), grid.push_back(0.01 * k);
  runtime::SimulationOptions options;
  options.relative_tolerance = 1e-11, options.absolute_tolerance = 1e-11;
  const auto sim = runtime::simulate(model, inputs, model.info().default_parameters(),
                                     runtime::OutputGrid::at(grid), options);
  REQUIRE(sim.ok());
  ex.data.outputs = {0, 1};
  ex.data.sigma = {0.01, 0.01};
  ex.data.values.resize(200, 2);
  const auto x = sim.trajectory.column("y_x"), phi = sim.trajectory.column("y_phi");
  std::mt19937 rng(7);
  std::normal_distribution<double> e(0.0, noise > 0 ? noise : 1.0);
  for (int k = 0; k < 200; ++k)
    ex.data.values(k, 0) = x[std::size_t(k) + 1] + (noise > 0 ? e(rng) : 0.0),
    ex.data.values(k, 1) = phi[std::size_t(k) + 1] + (noise > 0 ? e(rng) : 0.0);
  runtime::EstimationProblem p;
  p.experiments = {std::move(ex)};
  p.parameters = {runtime::FreeParameter{2, {0.1, 2.0}, 0.5}};
  p.collocation.n_e = 100, p.collocation.n_cp = 3;
  p.solver.hessian = mode;
  return p;
}

}  // namespace

TEST_CASE("estimation of m2 on a generated model: exact Hessian agrees with limited memory",
          "[hessian][estimate]") {
  auto model = compiled("cart_pendulum", cart_pendulum);
  for (double noise : {0.0, 0.01}) {
    runtime::EstimationResult r[2];
    double seconds[2];
    const runtime::HessianMode modes[2] = {runtime::HessianMode::exact,
                                           runtime::HessianMode::limited_memory};
    for (int k = 0; k < 2; ++k) {
      const runtime::EstimationProblem problem = m2_estimation(*model, modes[k], noise);
      const auto start = std::chrono::steady_clock::now();
      r[k] = runtime::estimate_parameters(*model, problem);
      seconds[k] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      INFO(r[k].message);  // HessianMode::exact fails (does not fall back) without model Hessians
      REQUIRE(r[k].status == runtime::OptimizationStatus::success);
    }
    std::cout << "generated cart pendulum, m2 (noise " << noise << ", n_e=100, n_cp=3): exact Hessian "
              << r[0].iterations << " iterations, " << seconds[0] << " s; limited memory "
              << r[1].iterations << " iterations, " << seconds[1] << " s; m2 " << r[0].estimate[0]
              << " / " << r[1].estimate[0] << "\n";
    CHECK(r[0].estimate[0] == Approx(1.0).margin(noise > 0 ? 0.05 : 1e-4));
    CHECK(r[0].estimate[0] == Approx(r[1].estimate[0]).margin(1e-5));
  }
}
