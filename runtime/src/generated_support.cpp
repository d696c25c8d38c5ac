// Equation-block drivers for generated code; see generated_support.hpp.
#include "mo/runtime/generated_support.hpp"

#include "mo/runtime/linear_solve.hpp"
#include "sparse_factors.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <string_view>

namespace mo::runtime::generated {

double delay_value(BlockWorkspace& ws, std::size_t line, double delay_time) {
  const double max = ws.delays.delay_max(line);
  if (!(delay_time >= 0.0 && delay_time <= max)) {
    if (ws.failure.empty())
      ws.failure = fmt::format("delay() at t = {}: the delay time {} is outside [0, delayMax = {}]", ws.time,
                               delay_time, max);
    return std::numeric_limits<double>::quiet_NaN();
  }
  return ws.delays.value(line, ws.time, delay_time);
}

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
  // The first failure of an evaluation is the cause; later blocks only see its NaN.
  // The description names the block, then (after the last "\n  equations: ",
  // which names cannot end with) lists its equations' source lines.
  if (ws.failure.empty()) {
    const std::string_view d(description);
    const auto eol = std::min(d.rfind("\n  equations: "), d.size());
    ws.failure = fmt::format("{} at t = {}: {}{}", d.substr(0, eol), ws.time, why, d.substr(eol));
  }
  return false;
}

/// The unknowns' values as "(z0, z1, ...)" for messages.
std::string iterate_text(const NonlinearBlock& b, const double* w) {
  std::string out = "(";
  for (int i = 0; i < b.size; ++i) out += fmt::format("{}{:g}", i ? ", " : "", w[b.unknowns[i]]);
  return out + ")";
}

double nominal_of(const NonlinearBlock& b, Size i) {
  return b.nominal && b.nominal[i] > 0 && std::isfinite(b.nominal[i]) ? b.nominal[i] : 1.0;
}

/// z clamped into the declared [min, max] of unknown i.
double within_bounds(const NonlinearBlock& b, Size i, double z) {
  if (b.lower && z < b.lower[i]) z = b.lower[i];
  if (b.upper && z > b.upper[i]) z = b.upper[i];
  return z;
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

/// ws.scale[i] = max_j |J_ij| · nominal_j from the assembled ws.a (1 for a zero row).
void row_scales(const NonlinearBlock& b, BlockWorkspace& ws) {
  const auto n = static_cast<Size>(b.size);
  ws.scale.assign(n, 0.0);
  for (Size i = 0; i < n; ++i) {
    for (Size j = 0; j < n; ++j)
      ws.scale[i] = std::max(ws.scale[i], std::fabs(ws.a[i * n + j]) * nominal_of(b, j));
    if (!(ws.scale[i] > 0.0) || !std::isfinite(ws.scale[i])) ws.scale[i] = 1.0;
  }
}

/// max |r_i| / scale_i, or +inf if some residual is not finite.
double scaled_norm(const NonlinearBlock& b, const double* w, const BlockWorkspace& ws) {
  double norm = 0.0;
  for (int i = 0; i < b.size; ++i) {
    const double r = w[b.residuals[i]];
    if (!std::isfinite(r)) return std::numeric_limits<double>::infinity();
    norm = std::max(norm, std::fabs(r) / ws.scale[static_cast<Size>(i)]);
  }
  return norm;
}

/// The largest λ in (0, 1] with z + λ dz within [lower, upper] (ws.z, ws.dz),
/// or 0 if an unknown on its bound points outward.
double step_to_bounds(const NonlinearBlock& b, const BlockWorkspace& ws) {
  double lambda = 1.0;
  for (Size i = 0; i < static_cast<Size>(b.size); ++i) {
    const double z = ws.z[i], dz = ws.dz[i];
    if (b.upper && dz > 0 && z + dz > b.upper[i]) lambda = std::min(lambda, (b.upper[i] - z) / dz);
    if (b.lower && dz < 0 && z + dz < b.lower[i]) lambda = std::min(lambda, (b.lower[i] - z) / dz);
  }
  return std::max(lambda, 0.0);
}

/// The Newton step where J (row-major, `jac`) is singular: the least-squares
/// one, (JᵀJ + μI) y = -Jᵀr over the unknowns in units of their nominal
/// values (dz = nominal·y), μ 1e-10 of the largest diagonal entry of JᵀJ; it
/// moves only along what the residuals see (the MSL's SaturatingInductor at
/// i = 0, where its inductance does not enter). Into ws.b; false if J is 0.
bool least_squares_step(const NonlinearBlock& b, const double* w, BlockWorkspace& ws,
                        const std::vector<double>& jac) {
  const auto n = static_cast<Size>(b.size);
  std::vector<double> normal(n * n, 0.0), rhs(n, 0.0);
  double largest = 0.0;
  for (Size j = 0; j < n; ++j) {
    for (Size k = 0; k < n; ++k) {
      double sum = 0.0;
      for (Size i = 0; i < n; ++i) sum += jac[i * n + j] * jac[i * n + k];
      normal[j * n + k] = sum * nominal_of(b, j) * nominal_of(b, k);
    }
    for (Size i = 0; i < n; ++i) rhs[j] -= jac[i * n + j] * nominal_of(b, j) * w[b.residuals[i]];
    largest = std::max(largest, normal[j * n + j]);
  }
  if (!(largest > 0.0) || !std::isfinite(largest)) return false;
  for (Size j = 0; j < n; ++j) normal[j * n + j] += 1e-10 * largest;
  if (!solve_dense(normal, ws.pivots, rhs)) return false;
  for (Size j = 0; j < n; ++j) ws.b[j] = rhs[j] * nominal_of(b, j);
  return true;
}

}  // namespace

namespace {

/// The singular block's minimum-norm solution z (into `rhs`, which holds -c)
/// from its matrix `a` (row-major), counted in ws.singular; false if its
/// equations contradict each other (then `rhs` is unchanged).
bool solve_singular(const LinearBlock& block, std::span<const double> a, std::span<double> rhs,
                    BlockWorkspace& ws) {
  if (!solve_minimum_norm(a, rhs)) return false;
  // By text: a section solving the model's steps again (the event
  // right-hand side) describes its blocks as the steps do.
  const std::string_view description(block.description);
  auto it = std::find_if(ws.singular.begin(), ws.singular.end(),
                         [&](const BlockWorkspace::SingularSolves& s) { return s.description == description; });
  if (it == ws.singular.end()) it = ws.singular.insert(it, {block.description, 0, ws.time});
  ++it->count;
  it->earliest = std::min(it->earliest, ws.time);  // a step tried beyond an event comes first
  return true;
}

/// Why a singular block could not be solved.
constexpr const char* kContradiction = "the matrix is singular and its equations contradict each other";

/// The largest singular block solved densely by its minimum-norm solution
/// (O(n³) per solve); a larger one fails as singular.
constexpr Size kMinimumNormMaxSize = 400;

/// solve_linear for a block of kSparseBlockSize unknowns or more: sparse LU,
/// the factors reused while the entries' values stay the same.
bool solve_linear_sparse(const LinearBlock& block, double* w, BlockWorkspace& ws) {
  const auto n = static_cast<Size>(block.size);
  const auto finite = [](double v) { return std::isfinite(v); };
  SparseFactors& f = ws.sparse.of(block);  // its own scratch: a torn block's Newton may be using ws
  f.values.resize(static_cast<Size>(block.num_entries));
  for (int k = 0; k < block.num_entries; ++k) f.values[static_cast<Size>(k)] = w[block.entries[k].slot];
  f.rhs.resize(n);
  for (Size i = 0; i < n; ++i) f.rhs[i] = -w[block.offsets[i]];
  if (!std::all_of(f.values.begin(), f.values.end(), finite) ||
      !std::all_of(f.rhs.begin(), f.rhs.end(), finite))
    return fail(block.description, block.unknowns, n, w, ws,
                "its coefficients are not finite (a value it uses is NaN or infinite)");
  const std::string why = solve_sparse(f, block);
  if (!why.empty()) {
    if (n > kMinimumNormMaxSize) return fail(block.description, block.unknowns, n, w, ws, why);
    ws.a.assign(n * n, 0.0);  // J dense, for its minimum-norm solution
    for (int k = 0; k < block.num_entries; ++k)
      ws.a[static_cast<Size>(block.entries[k].row) * n + static_cast<Size>(block.entries[k].col)] =
          f.values[static_cast<Size>(k)];
    for (Size i = 0; i < n; ++i) f.rhs[i] = -w[block.offsets[i]];
    if (!solve_singular(block, ws.a, f.rhs, ws))
      return fail(block.description, block.unknowns, n, w, ws, kContradiction);
  }
  for (Size i = 0; i < n; ++i) w[block.unknowns[i]] = f.rhs[i];
  return true;
}

}  // namespace

bool solve_linear(const LinearBlock& block, double* w, BlockWorkspace& ws) {
  if (block.size >= kSparseBlockSize) return solve_linear_sparse(block, w, ws);
  const auto n = static_cast<Size>(block.size);
  ws.a.resize(n * n);
  ws.b.resize(n);
  assemble(block.entries, block.num_entries, n, w, ws);
  const auto finite = [](double v) { return std::isfinite(v); };
  for (Size i = 0; i < n; ++i) ws.b[i] = -w[block.offsets[i]];
  if (ws.a != ws.factored) {  // NaN never compares equal: refactorised, then refused
    ws.factored.clear();
    if (!std::all_of(ws.a.begin(), ws.a.end(), finite))
      return fail(block.description, block.unknowns, n, w, ws,
                  "its coefficients are not finite (a value it uses is NaN or infinite)");
    ws.lu = ws.a;
    ws.lu_pivots.resize(n);
    if (lu_factor(ws.lu, ws.lu_pivots)) ws.factored = ws.a;
  }
  if (!std::all_of(ws.b.begin(), ws.b.end(), finite))
    return fail(block.description, block.unknowns, n, w, ws,
                "its coefficients are not finite (a value it uses is NaN or infinite)");
  if (ws.factored.empty()) {  // singular: not factorised
    if (!solve_singular(block, ws.a, ws.b, ws))
      return fail(block.description, block.unknowns, n, w, ws, kContradiction);
  } else {
    lu_solve(ws.lu, ws.lu_pivots, ws.b);
  }
  for (Size i = 0; i < n; ++i) w[block.unknowns[i]] = ws.b[i];
  return true;
}

std::vector<std::string> singular_notes(const BlockWorkspace& ws) {
  std::vector<std::string> out;
  for (const auto& s : ws.singular) {
    const std::string_view d(s.description);
    // The model's own blocks; the sections derived from them (Jacobian-vector
    // products, event tangents, ...) solve the same matrices.
    if (!d.starts_with("linear block ") && !d.starts_with("initial system: linear block ")) continue;
    out.push_back(fmt::format("{} was singular in {} solve{}, the earliest at t = {}: its equations leave part of it "
                              "undetermined, and their minimum-norm solution was taken",
                              d.substr(0, std::min(d.find('\n'), d.size())), s.count, s.count == 1 ? "" : "s",
                              s.earliest));
  }
  return out;
}

namespace {

/// Damped Newton from w[unknowns]; empty on success, else why it failed (the
/// unknowns hold the last iterate).
std::string newton(const NonlinearBlock& block, double* w, BlockWorkspace& ws) {
  const auto n = static_cast<Size>(block.size);
  const NewtonOptions& opt = ws.newton;
  prepare(ws, n);
  block.evaluate(w, ws.cross);
  double norm = residual_norm(block, w);
  if (!std::isfinite(norm)) return "the residuals are not finite at the start guess " + iterate_text(block, w);
  for (int iteration = 0; iteration < opt.max_iterations; ++iteration) {
    if (norm <= opt.residual_tolerance) return {};
    assemble(block.entries, block.num_entries, n, w, ws);
    row_scales(block, ws);
    const double merit = scaled_norm(block, w, ws);
    for (Size i = 0; i < n; ++i) ws.b[i] = -w[block.residuals[i]];
    if (!solve_dense(ws.a, ws.pivots, ws.b)) {
      assemble(block.entries, block.num_entries, n, w, ws);  // solve_dense factorised it in place
      if (!least_squares_step(block, w, ws, ws.a))
        return fmt::format("singular Jacobian at Newton iteration {}", iteration);
    }
    bool small_step = true;
    for (Size i = 0; i < n; ++i) {
      ws.z[i] = w[block.unknowns[i]];
      ws.dz[i] = ws.b[i];
      small_step = small_step &&
                   std::fabs(ws.dz[i]) <= opt.step_tolerance * (nominal_of(block, i) + std::fabs(ws.z[i]));
    }
    // Damping: halve the step until the residual norm decreases (Armijo-like).
    // The step is first shortened to stay within the unknowns' bounds (its
    // direction kept); if an unknown on its bound points outward, the trial
    // points are projected onto the bounds instead.
    // The merit is the residual in units of each equation's sensitivity to
    // the unknowns at their nominal scale, so that an equation in pascals
    // does not outweigh one in fractions.
    double lambda = step_to_bounds(block, ws), trial = merit;
    if (lambda <= 0.0) lambda = 1.0;
    for (int halving = 0; halving <= opt.max_halvings; ++halving, lambda *= 0.5) {
      for (Size i = 0; i < n; ++i)
        w[block.unknowns[i]] = within_bounds(block, i, ws.z[i] + lambda * ws.dz[i]);
      block.evaluate(w, ws.cross);
      trial = scaled_norm(block, w, ws);
      if (trial < (1 - 1e-4 * lambda) * merit) break;
    }
    if (!std::isfinite(trial))
      return fmt::format("residuals not finite along the Newton step at iteration {} from {}", iteration,
                         iterate_text(block, w));
    norm = residual_norm(block, w);
    if (small_step) return {};
  }
  if (norm <= opt.residual_tolerance) return {};
  return fmt::format("Newton did not converge in {} iterations (max |residual| = {:g} at {})",
                     opt.max_iterations, norm, iterate_text(block, w));
}

/// The residual of a one-unknown block at z (finite or not).
double scalar_residual(const NonlinearBlock& b, double* w, const int* cross, double z) {
  w[b.unknowns[0]] = z;
  b.evaluate(w, cross);
  return w[b.residuals[0]];
}

/// A one-unknown block Newton could not solve, by bracketing from z0: points
/// on both sides, 1e-8 of the scale away and twice as far each time (within
/// the bounds), until the residual changes sign between two neighbours on
/// one side; then the Illinois method (regula falsi that halves the weight of
/// an end kept twice) closes in to rounding. Newton cycles on a residual made
/// of a steep piece between two flat ones (a limiter in a feedback loop, the
/// MSL's op-amps); a bracketed sign change is not lost. True with
/// w[unknown] at the root; false where the sign changes by a jump (|r| left
/// above `tolerance` and 1e-9 of its value at z0).
bool bracket_scalar(const NonlinearBlock& b, double* w, const int* cross, double z0, double tolerance) {
  const double f0 = scalar_residual(b, w, cross, z0);
  if (!std::isfinite(f0)) return false;
  if (f0 == 0.0) return true;
  const double scale = std::max(nominal_of(b, 0), std::fabs(z0));
  double lo = 0, flo = 0, hi = 0, fhi = 0;
  double last[2] = {z0, z0}, f_last[2] = {f0, f0};  // nearest point tried per side
  bool found = false;
  for (int k = 0; k < 120 && !found; ++k) {
    for (int side = 0; side < 2 && !found; ++side) {
      const double z = within_bounds(b, 0, z0 + (side ? -1.0 : 1.0) * 1e-8 * scale * std::ldexp(1.0, k));
      if (z == last[side]) continue;  // on a bound
      const double f = scalar_residual(b, w, cross, z);
      if (!std::isfinite(f)) continue;
      if ((f < 0) != (f_last[side] < 0) || f == 0.0) {
        lo = side ? z : last[side], flo = side ? f : f_last[side];
        hi = side ? last[side] : z, fhi = side ? f_last[side] : f;
        found = true;
      }
      last[side] = z, f_last[side] = f;
    }
  }
  if (!found) return false;
  int kept = 0;  // +1: hi was replaced last time, -1: lo was
  for (int k = 0; k < 400 && flo != 0.0 && fhi != 0.0; ++k) {
    double z = (lo * fhi - hi * flo) / (fhi - flo);
    if (!(z > lo && z < hi)) z = lo + (hi - lo) / 2;
    if (!(z > lo && z < hi)) break;  // no double between them
    const double f = scalar_residual(b, w, cross, z);
    if (!std::isfinite(f)) return false;
    if ((f < 0) == (fhi < 0)) {
      hi = z, fhi = f;
      if (kept == 1) flo /= 2;
      kept = 1;
    } else {
      lo = z, flo = f;
      if (kept == -1) fhi /= 2;
      kept = -1;
    }
  }
  const double f_lo = scalar_residual(b, w, cross, lo), f_hi = scalar_residual(b, w, cross, hi);
  if (std::fabs(f_lo) <= std::fabs(f_hi)) scalar_residual(b, w, cross, lo);
  return std::min(std::fabs(f_lo), std::fabs(f_hi)) <= std::max(tolerance, 1e-9 * std::fabs(f0));
}

}  // namespace

namespace {

/// Newton continues in time: it starts from the block's latest solution at a
/// time not after this evaluation's. An integrator's rejected trial step
/// far ahead (where a hysteresis has switched to its other solution) then
/// does not decide the solution at the earlier times it retries.
void start_from_past(const NonlinearBlock& block, double* w, BlockWorkspace& ws) {
  auto it = ws.solutions.find(&block);
  if (it == ws.solutions.end()) return;
  auto& past = it->second;
  while (!past.empty() && past.back().time > ws.time) past.pop_back();
  if (past.empty()) return;
  for (std::size_t i = 0; i < past.back().z.size(); ++i) w[block.unknowns[i]] = past.back().z[i];
}

void remember_solution(const NonlinearBlock& block, const double* w, BlockWorkspace& ws) {
  constexpr std::size_t kKept = 16;
  auto& past = ws.solutions[&block];
  if (past.empty() || past.back().time < ws.time) {
    if (past.size() == kKept) past.erase(past.begin());
    past.push_back({ws.time, std::vector<double>(static_cast<std::size_t>(block.size))});
  }
  for (int i = 0; i < block.size; ++i) past.back().z[static_cast<std::size_t>(i)] = w[block.unknowns[i]];
}

}  // namespace

bool solve_nonlinear(const NonlinearBlock& block, double* w, BlockWorkspace& ws) {
  const auto n = static_cast<Size>(block.size);
  if (ws.follow_time) start_from_past(block, w, ws);
  for (Size i = 0; i < n; ++i) {  // a NaN left by an earlier failure is no start
    double& z = w[block.unknowns[i]];
    z = within_bounds(block, i, std::isfinite(z) ? z : 0.0);
  }
  const double z0 = w[block.unknowns[0]];
  const std::string why = newton(block, w, ws);
  if (why.empty() || (n == 1 && bracket_scalar(block, w, ws.cross, z0, ws.newton.residual_tolerance))) {
    if (ws.follow_time) remember_solution(block, w, ws);
    return true;
  }
  return fail(block.description, block.unknowns, n, w, ws, why);
}

}  // namespace mo::runtime::generated
