// Generated C++ against the symbolic evaluator (rhs, outputs), finite
// differences and the hand-derived cart-pendulum Jacobians; linear and
// nonlinear blocks; the compile cache.
#include <catch2/catch.hpp>

#include <filesystem>
#include <random>

#include "codegen/jacobian_check.hpp"
#include "codegen/models.hpp"
#include "codegen/support.hpp"
#include "mo/runtime/simulate.hpp"
#include "mo/symbolic/sensitivities.hpp"
#include "runtime/fixtures.hpp"

using namespace mo;
using namespace mo::codegen::test;
using runtime::Jacobian;

namespace {

struct Point {
  double t;
  std::vector<double> x, u, p;
};

Point random_cart_point(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1, 1), scale(0.8, 1.2);
  return {unit(rng), {unit(rng), 3 * unit(rng), unit(rng), 2 * unit(rng)}, {5 * unit(rng)},
          {2 * scale(rng), 15 * scale(rng), scale(rng), 0.5 * scale(rng), 0.5 * scale(rng)}};
}

}  // namespace

TEST_CASE("cart pendulum: generated rhs and outputs equal the symbolic evaluator") {
  auto model = compiled("cart_pendulum", cart_pendulum);
  const symbolic::OdeModel reference_model = cart_pendulum();
  std::mt19937 rng(1);
  for (int k = 0; k < 20; ++k) {
    const Point pt = random_cart_point(rng);
    std::vector<double> xdot(4), y(2);
    model->rhs(pt.t, pt.x, pt.u, pt.p, xdot);
    model->outputs(pt.t, pt.x, pt.u, pt.p, y);
    const ReferencePoint ref = reference(reference_model, pt.t, pt.x, pt.u, pt.p);
    for (std::size_t i = 0; i < 4; ++i) CHECK(close(xdot[i], ref.xdot[i], 1e-12));
    for (std::size_t i = 0; i < 2; ++i) CHECK(close(y[i], ref.y[i], 1e-14));
    CHECK(model->last_failure().empty());
  }
}

TEST_CASE("cart pendulum: info() has names, units, descriptions, defaults") {
  auto model = compiled("cart_pendulum", cart_pendulum);
  const runtime::ModelInfo& info = model->info();
  CHECK(info.name == "CartPendulumODE");
  REQUIRE(info.states.size() == 4);
  CHECK(info.states[0].name == "x");
  CHECK(info.states[0].unit == "m");
  CHECK(info.states[0].description == "Cart position (m)");
  CHECK(info.inputs.at(0).description == "Force on the cart (N)");
  CHECK(info.outputs.at(1).name == "y_phi");
  CHECK(info.default_parameters() == std::vector<double>{2, 15, 1, 0.5, 0.5});
  CHECK(info.num_event_indicators == 0);
  CHECK(&model->info() == &model->clone()->info());
}

TEST_CASE("cart pendulum: every Jacobian block matches finite differences") {
  auto model = compiled("cart_pendulum", cart_pendulum);
  std::mt19937 rng(2);
  for (int k = 0; k < 5; ++k) {
    const Point pt = random_cart_point(rng);
    check_jacobians(*model, pt.t, pt.x, pt.u, pt.p);
  }
}

TEST_CASE("cart pendulum: Jacobians equal the hand-derived fixture's, pattern included") {
  auto model = compiled("cart_pendulum", cart_pendulum);
  runtime::fixtures::CartPendulum hand;
  std::mt19937 rng(3);
  const Point pt = random_cart_point(rng);
  for (Jacobian b : {Jacobian::f_x, Jacobian::f_u, Jacobian::f_p, Jacobian::h_x, Jacobian::h_u,
                     Jacobian::h_p, Jacobian::x0_p}) {
    const auto& sp = model->jacobian_sparsity(b);
    const auto& hs = hand.jacobian_sparsity(b);
    CHECK(sp.col_start == hs.col_start);
    CHECK(sp.row_index == hs.row_index);
    std::vector<double> mine(static_cast<std::size_t>(sp.nnz())), theirs(mine.size());
    model->jacobian_values(b, pt.t, pt.x, pt.u, pt.p, mine);
    hand.jacobian_values(b, pt.t, pt.x, pt.u, pt.p, theirs);
    for (std::size_t k = 0; k < mine.size(); ++k) CHECK(close(mine[k], theirs[k], 1e-11));
  }
}

TEST_CASE("cart pendulum: simulation equals the hand-written fixture's") {
  auto model = compiled("cart_pendulum", cart_pendulum);
  runtime::fixtures::CartPendulum hand;
  auto inputs = [] {
    runtime::Inputs in;
    in.add(runtime::sine_input(3.0, 1.0));
    return in;
  };
  const auto grid = runtime::OutputGrid::uniform(0, 5, 50);
  runtime::SimulationOptions opt;
  opt.relative_tolerance = 1e-10;
  opt.absolute_tolerance = 1e-12;
  const auto p = hand.info().default_parameters();
  const auto mine = runtime::simulate(*model, inputs(), p, grid, opt);
  const auto theirs = runtime::simulate(hand, inputs(), p, grid, opt);
  REQUIRE(mine.ok());
  REQUIRE(theirs.ok());
  for (std::size_t k = 0; k < mine.trajectory.rows(); ++k)
    for (std::size_t j = 0; j < 6; ++j) CHECK(close(mine.trajectory.at(k, j), theirs.trajectory.at(k, j), 1e-7));
}

TEST_CASE("a singular linear block: its minimum-norm solution if consistent, else NaN and which block") {
  auto model = compiled("cart_pendulum", cart_pendulum);
  // m2 = 0: the pendulum's row is 0·der(v) + 0·der(w) = -d2·w.
  std::vector<double> xdot(4), x{0, 0, 0, 0.3}, u{1}, p{2, 15, 0, 0.5, 0.5};
  model->rhs(1.5, x, u, p, xdot);  // w ≠ 0: the row contradicts itself
  CHECK(std::isnan(xdot[2]));
  CHECK(std::isnan(xdot[3]));
  CHECK(model->last_failure() ==
        "linear block 1 for der(v), der(w) at t = 1.5: the matrix is singular and its equations contradict each other");
  x[3] = 0;  // w = 0: der(w) undetermined, its least-norm value 0; der(v) = F/m1
  model->rhs(1.5, x, u, p, xdot);
  CHECK(xdot[2] == Approx(0.5).epsilon(1e-14));
  CHECK(xdot[3] == 0.0);
  CHECK(model->last_failure().empty());
  const std::vector<double> start(4, 0.0);
  std::vector<double> x0(4);
  model->initial_state(0.0, u, p, x0);  // notes count from here
  CHECK(model->notes().empty());
  model->rhs(1.5, start, u, p, xdot);
  REQUIRE(model->notes().size() == 1);
  CHECK(model->notes()[0].find("linear block 1 for der(v), der(w) was singular in 1 solve, the earliest at t = 1.5:") == 0);
  p[2] = 1;
  x[3] = 0.3;
  model->rhs(1.5, x, u, p, xdot);
  CHECK(std::isfinite(xdot[3]));
  CHECK(model->last_failure().empty());
}

TEST_CASE("nonlinear block: Newton result, outputs and Jacobians") {
  auto model = compiled("cubic_root", cubic_root);
  const symbolic::OdeModel reference_model = cubic_root();
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> xs(-5, 5), ks(0.5, 2);
  std::vector<double> x0(1);
  model->initial_state(std::vector<double>{1.0, 2.0}, x0);
  CHECK(x0[0] == 4.0);
  for (int k = 0; k < 10; ++k) {
    const std::vector<double> x{xs(rng)}, p{ks(rng), 2.0};
    std::vector<double> xdot(1), y(2);
    model->rhs(0.0, x, {}, p, xdot);
    model->outputs(0.0, x, {}, p, y);
    const double z = y[1];
    CHECK(std::fabs(z * z * z + p[0] * z - x[0]) < 1e-12);
    const ReferencePoint ref = reference(reference_model, 0.0, x, {}, p);
    CHECK(close(xdot[0], ref.xdot[0], 1e-10));
    CHECK(close(y[0], ref.y[0], 1e-10));
    check_jacobians(*model, 0.0, x, {}, p);
  }
}

TEST_CASE("nonlinear block failure is reported, not thrown") {
  auto model = compiled("cubic_root", cubic_root);
  std::vector<double> xdot(1), x{1.0}, p{std::nan(""), 2.0};
  model->rhs(0.0, x, {}, p, xdot);
  CHECK(std::isnan(xdot[0]));
  CHECK_THAT(model->last_failure(), Catch::StartsWith("nonlinear block 1 for z at t = 0: "));
}

TEST_CASE("sensitivity states from add_sensitivities simulate like CVODES' sensitivities") {
  auto build = [] {
    symbolic::OdeModel m = cart_pendulum();
    const std::vector<std::size_t> params{2};  // m2
    symbolic::add_sensitivities(m, params);
    return m;
  };
  auto with = compiled("cart_pendulum_sens", build);
  auto base = compiled("cart_pendulum", cart_pendulum);
  const auto& info = with->info();
  REQUIRE(info.states.size() > 4);
  CHECK(info.states[4].sensitivity.has_value());
  CHECK(info.num_base_states() == 4);
  const auto grid = runtime::OutputGrid::uniform(0, 3, 30);
  runtime::SimulationOptions opt;
  opt.relative_tolerance = 1e-10;
  opt.absolute_tolerance = 1e-12;
  auto inputs = [] {
    runtime::Inputs in;
    in.add(runtime::sine_input(3.0, 1.0));
    return in;
  };
  const auto p = info.default_parameters();
  opt.sensitivities.method = runtime::SensitivityMethod::model_states;
  const auto mine = runtime::simulate(*with, inputs(), p, grid, opt);
  opt.sensitivities.method = runtime::SensitivityMethod::cvodes_analytic;
  opt.sensitivities.parameters = {2};
  const auto theirs = runtime::simulate(*base, inputs(), p, grid, opt);
  REQUIRE(mine.ok());
  REQUIRE(theirs.ok());
  for (std::size_t k = 0; k < grid.times.size(); ++k)
    for (Eigen::Index i = 0; i < 4; ++i)
      CHECK(close(mine.state_sensitivities[k](i, 0), theirs.state_sensitivities[k](i, 0), 1e-6));
  std::mt19937 rng(5);
  Point pt = random_cart_point(rng);
  std::vector<double> x(info.states.size(), 0.1);
  std::copy(pt.x.begin(), pt.x.end(), x.begin());
  check_jacobians(*with, pt.t, x, pt.u, pt.p, 1e-5);
}

TEST_CASE("the second compilation of the same sources is a cache hit", "[slow]") {
  symbolic::OdeModel m = cubic_root();
  codegen::CodegenOptions opt;
  opt.name = "cache_probe";
  const auto src = codegen::generate_cpp(m, opt);
  auto o = test_compiler_options();
  o.cache_dir = std::string(MO_BINARY_DIR) + "/codegen-test-cache-probe";
  std::filesystem::remove_all(o.cache_dir);
  const auto first = codegen::compile_shared_object(src, o);
  CHECK_FALSE(first.cached);
  CHECK(first.seconds > 0);
  const auto second = codegen::compile_shared_object(src, o);
  CHECK(second.cached);
  CHECK(second.library == first.library);
  o.flags.push_back("-DMO_DIFFERENT_FLAGS");
  CHECK(codegen::compile_shared_object(src, o).key != first.key);
  codegen::LoadedModel loaded(second.library, src.factory_symbol);
  CHECK(loaded.create()->info().name == "CubicRoot");
}

TEST_CASE("large models are split over several translation units") {
  symbolic::OdeModel m = spring_chain(200);
  codegen::CodegenOptions opt;
  opt.name = "chain200";
  opt.instructions_per_function = 100;
  opt.instructions_per_file = 500;
  const auto src = codegen::generate_cpp(m, opt);
  CHECK(src.sources().size() > 3);
  CHECK(src.instructions > 1000);
}

TEST_CASE("a spring chain split into many files compiles and matches the evaluator", "[slow]") {
  auto build = [] { return spring_chain(30); };
  symbolic::OdeModel m = build();
  codegen::CodegenOptions opt;
  opt.name = "chain30";
  opt.instructions_per_function = 40;
  opt.instructions_per_file = 200;
  const auto src = codegen::generate_cpp(m, opt);
  REQUIRE(src.sources().size() > 3);
  const auto so = codegen::compile_shared_object(src, test_compiler_options());
  auto model = codegen::LoadedModel(so.library, src.factory_symbol).create();
  const symbolic::OdeModel ref_model = build();
  std::vector<double> x(60), p(90), u{0.3}, xdot(60);
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> r(0.5, 1.5);
  for (auto& v : x) v = r(rng) - 1;
  for (auto& v : p) v = r(rng);
  model->rhs(0, x, u, p, xdot);
  const auto ref = reference(ref_model, 0, x, u, p);
  for (std::size_t i = 0; i < 60; ++i) CHECK(close(xdot[i], ref.xdot[i], 1e-12));
  // Tridiagonal-by-unit f_x: a handful of colours, not 60.
  CHECK(model->jacobian_sparsity(Jacobian::f_x).nnz() < 60 * 6);
  check_jacobians(*model, 0, x, u, p);
}
