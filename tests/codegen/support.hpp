// Compiling hand-built models once per test process, and an independent
// reference: the OdeModel's steps evaluated by the symbolic evaluator with
// blocks solved by Eigen.
#pragma once

#include <Eigen/Dense>

#include <functional>
#include <map>
#include <memory>
#include <string>

#include "mo/codegen/generate.hpp"
#include "mo/codegen/shared_object.hpp"
#include "mo/symbolic/evaluator.hpp"

namespace mo::codegen::test {

/// Compile options for tests: this build's runtime headers, the tests' cache (MO_TEST_CACHE_DIR).
inline CompilerOptions test_compiler_options() {
  CompilerOptions o = runtime_compiler_options();
  o.cache_dir = std::string(MO_TEST_CACHE_DIR) + "/codegen-test-cache";
  o.jobs = 2;
  return o;
}

/// A model generated, compiled (or found in the cache) and loaded once per
/// process under `name`; each call returns a fresh instance.
inline std::unique_ptr<runtime::Model> compiled(const std::string& name,
                                                const std::function<symbolic::OdeModel()>& build) {
  static std::map<std::string, std::unique_ptr<LoadedModel>> loaded;
  auto& slot = loaded[name];
  if (!slot) {
    symbolic::OdeModel m = build();
    CodegenOptions opt;
    opt.name = name;
    const GeneratedSources src = generate_cpp(m, opt);
    const CompiledModel so = compile_shared_object(src, test_compiler_options());
    slot = std::make_unique<LoadedModel>(so.library, src.factory_symbol);
  }
  return slot->create();
}

/// Values of every step target, state derivative and output at one point.
struct ReferencePoint {
  std::vector<double> xdot, y;
};

/// Evaluates the steps in order with the symbolic evaluator; linear blocks by
/// Eigen's LU, nonlinear blocks by plain Newton from their start values.
inline ReferencePoint reference(const symbolic::OdeModel& m, double t, std::span<const double> x,
                                std::span<const double> u, std::span<const double> p,
                                std::span<const double> d = {}) {
  symbolic::LeafValues v;
  v[m.time] = t;
  for (std::size_t i = 0; i < m.states.size(); ++i) v[m.states[i].symbol] = x[i];
  for (std::size_t i = 0; i < m.inputs.size(); ++i) v[m.inputs[i].symbol] = u[i];
  for (std::size_t i = 0; i < m.parameters.size(); ++i) v[m.parameters[i].symbol] = p[i];
  for (std::size_t i = 0; i < m.discrete.size(); ++i)
    v[m.discrete[i].symbol] = i < d.size() ? d[i] : m.discrete[i].start;
  auto eval = [&](std::span<const symbolic::Expr> es) { return symbolic::evaluate(m.arena, es, v); };
  for (const auto& step : m.steps) {
    if (const auto* as = std::get_if<symbolic::Assignment>(&step)) {
      v[as->target] = eval(std::span(&as->value, 1))[0];
      continue;
    }
    const auto& b = std::get<symbolic::EquationBlock>(step);
    const auto n = static_cast<Eigen::Index>(b.unknowns.size());
    auto matrix = [&] {
      Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n, n);
      for (const auto& e : b.jacobian)
        J(static_cast<Eigen::Index>(e.row), static_cast<Eigen::Index>(e.col)) = eval(std::span(&e.value, 1))[0];
      return J;
    };
    if (b.linear) {
      const std::vector<double> c = eval(b.offset);
      const Eigen::VectorXd z = matrix().lu().solve(-Eigen::Map<const Eigen::VectorXd>(c.data(), n));
      for (Eigen::Index i = 0; i < n; ++i) v[b.unknowns[static_cast<std::size_t>(i)]] = z[i];
      continue;
    }
    for (Eigen::Index i = 0; i < n; ++i) v[b.unknowns[static_cast<std::size_t>(i)]] = b.start[static_cast<std::size_t>(i)];
    for (int it = 0; it < 100; ++it) {
      const std::vector<double> r = eval(b.residuals);
      const Eigen::VectorXd dz = matrix().lu().solve(-Eigen::Map<const Eigen::VectorXd>(r.data(), n));
      for (Eigen::Index i = 0; i < n; ++i) v[b.unknowns[static_cast<std::size_t>(i)]] += dz[i];
      if (dz.norm() < 1e-14) break;
    }
  }
  ReferencePoint out;
  for (const auto& s : m.states) out.xdot.push_back(v.at(s.derivative));
  for (const auto& y : m.outputs) out.y.push_back(eval(std::span(&y.value, 1))[0]);
  return out;
}

/// |a - b| <= tol · max(1, |a|, |b|).
inline bool close(double a, double b, double tol) {
  return std::fabs(a - b) <= tol * std::max({1.0, std::fabs(a), std::fabs(b)});
}

}  // namespace mo::codegen::test
