// Equation-block drivers for generated code; see generated_support.hpp.
#include "mo/runtime/generated_support.hpp"

#include "mo/runtime/linear_solve.hpp"

#include <algorithm>
#include <fmt/format.h>

namespace mo::runtime::generated {

namespace {

using Size = std::size_t;

void prepare(BlockWorkspace& ws, Size n) {
  ws.a.assign(n * n, 0.0);
  ws.b.resize(n);
  ws.z.resize(n);
  ws.dz.resize(n);
  ws.pivots.resize(n);
}

void assemble(const BlockEntry* entries, int count, Size n, const double* w, BlockWorkspace& ws) {
  std::fill(ws.a.begin(), ws.a.end(), 0.0);
  for (int k = 0; k < count; ++k) {
    const BlockEntry& e = entries[k];
    ws.a[static_cast<Size>(e.row) * n + static_cast<Size>(e.col)] = w[e.slot];
  }
}

bool fail(const char* description, const int* unknowns, Size n, double* w, BlockWorkspace& ws,
          const std::string& why) {
  for (Size i = 0; i < n; ++i) w[unknowns[i]] = std::numeric_limits<double>::quiet_NaN();
  ws.failure = fmt::format("{} at t = {}: {}", description, ws.time, why);
  return false;
}

/// max |r_i|, or +inf if some residual is not finite.
double residual_norm(const NonlinearBlock& b, const double* w) {
  double norm = 0.0;
  for (int i = 0; i < b.size; ++i) {
    const double r = w[b.residuals[i]];
    if (!std::isfinite(r)) return std::numeric_limits<double>::infinity();
    norm = std::max(norm, std::fabs(r));
  }
  return norm;
}

}  // namespace

bool solve_linear(const LinearBlock& block, double* w, BlockWorkspace& ws) {
  const auto n = static_cast<Size>(block.size);
  prepare(ws, n);
  assemble(block.entries, block.num_entries, n, w, ws);
  for (Size i = 0; i < n; ++i) ws.b[i] = -w[block.offsets[i]];
  if (!solve_dense(ws.a, ws.pivots, ws.b))
    return fail(block.description, block.unknowns, n, w, ws, "the matrix is singular");
  for (Size i = 0; i < n; ++i) w[block.unknowns[i]] = ws.b[i];
  return true;
}

bool solve_nonlinear(const NonlinearBlock& block, double* w, BlockWorkspace& ws) {
  const auto n = static_cast<Size>(block.size);
  const NewtonOptions& opt = ws.newton;
  prepare(ws, n);
  for (Size i = 0; i < n; ++i)  // a NaN left by an earlier failure is no start
    if (!std::isfinite(w[block.unknowns[i]])) w[block.unknowns[i]] = 0.0;
  block.evaluate(w);
  double norm = residual_norm(block, w);
  if (!std::isfinite(norm))
    return fail(block.description, block.unknowns, n, w, ws,
                "the residuals are not finite at the start guess");
  for (int iteration = 0; iteration < opt.max_iterations; ++iteration) {
    if (norm <= opt.residual_tolerance) return true;
    assemble(block.entries, block.num_entries, n, w, ws);
    for (Size i = 0; i < n; ++i) ws.b[i] = -w[block.residuals[i]];
    if (!solve_dense(ws.a, ws.pivots, ws.b))
      return fail(block.description, block.unknowns, n, w, ws,
                  fmt::format("singular Jacobian at Newton iteration {}", iteration));
    bool small_step = true;
    for (Size i = 0; i < n; ++i) {
      ws.z[i] = w[block.unknowns[i]];
      ws.dz[i] = ws.b[i];
      small_step = small_step && std::fabs(ws.dz[i]) <= opt.step_tolerance * (1 + std::fabs(ws.z[i]));
    }
    // Damping: halve the step until the residual norm decreases (Armijo-like).
    double lambda = 1.0, trial = norm;
    for (int halving = 0; halving <= opt.max_halvings; ++halving, lambda *= 0.5) {
      for (Size i = 0; i < n; ++i) w[block.unknowns[i]] = ws.z[i] + lambda * ws.dz[i];
      block.evaluate(w);
      trial = residual_norm(block, w);
      if (trial < (1 - 1e-4 * lambda) * norm) break;
    }
    if (!std::isfinite(trial))
      return fail(block.description, block.unknowns, n, w, ws,
                  fmt::format("residuals not finite along the Newton step at iteration {}",
                              iteration));
    norm = trial;
    if (small_step) return true;
  }
  if (norm <= opt.residual_tolerance) return true;
  return fail(block.description, block.unknowns, n, w, ws,
              fmt::format("Newton did not converge in {} iterations (max |residual| = {:g})",
                          opt.max_iterations, norm));
}

}  // namespace mo::runtime::generated
