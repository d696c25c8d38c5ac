// What generated model code calls besides the Model interface: scalar
// functions whose semantics must match the symbolic evaluator exactly, and
// the drivers of equation blocks.
//
//   linear block     J z = -c          J, c read from work slots, LU with pivoting
//   nonlinear block  0 = r(z)          damped Newton on the generated J, starting
//                                      from the unknowns' current slot values
//
// Generated code keeps every value in one work array `w` (one slot per
// expression node or variable); blocks name their unknowns, residuals and
// Jacobian entries by slot. A failed block sets its unknowns to NaN and
// records why in the workspace; evaluation itself never throws.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "mo/runtime/delay_lines.hpp"
#include "mo/runtime/modelica_random.hpp"

namespace mo::runtime::generated {

/// sign(a): 1, -1 or 0; NaN for NaN (as the symbolic evaluator).
inline double sign(double a) {
  if (std::isnan(a)) return a;
  return a > 0 ? 1.0 : (a < 0 ? -1.0 : 0.0);
}
/// True while the indicator a - b of a relation crossed at this instant, and
/// that reads a discrete variable, is still at its zero, within rounding and
/// the event iteration's Newton tolerance (1e-6 of max(1, |a|, |b|)): the
/// relation keeps the value of its crossing's direction. One that a clause
/// moved away (a timer's `time >= t_start + waitTime` once t_start := time)
/// takes its value again.
inline bool held_at_zero(double a, double b) {
  return std::abs(a - b) <= 1e-6 * std::max({1.0, std::abs(a), std::abs(b)});
}
/// Output `code` of a ModelicaExternalC random generator at the state `args`
/// (ExprKind::External; mo/runtime/modelica_random.hpp).
inline double modelica_random(double code, std::initializer_list<double> args) {
  return mo::runtime::modelica_random::value(static_cast<int>(code), std::span(args.begin(), args.size()));
}
/// min(a, b); NaN if either operand is NaN (commutative).
inline double min(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<double>::quiet_NaN();
  return a < b ? a : b;
}
/// max(a, b); NaN if either operand is NaN (commutative).
inline double max(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<double>::quiet_NaN();
  return a > b ? a : b;
}

/// J(row, col) = w[slot].
struct BlockEntry {
  int row;   ///< residual index
  int col;   ///< unknown index
  int slot;  ///< work slot holding the value
};

/// A linear block J z = -c, evaluated before the solve.
struct LinearBlock {
  int size;                   ///< number of unknowns n
  const int* unknowns;        ///< n slots receiving z
  const int* offsets;         ///< n slots holding c (the residuals at z = 0)
  const BlockEntry* entries;  ///< structurally nonzero J entries
  int num_entries;            ///< number of entries
  const char* description;    ///< e.g. "linear block 2 for der(v), der(w)", for messages
};

/// A nonlinear block 0 = r(z) with Jacobian entries, both computed by `evaluate`.
struct NonlinearBlock {
  int size;                   ///< number of unknowns n
  const int* unknowns;        ///< n slots holding z (the start guess on entry)
  const int* residuals;       ///< n slots receiving r(z) from evaluate
  const BlockEntry* entries;  ///< J entries, computed by evaluate too
  int num_entries;            ///< number of entries
  /// Computes residuals and entries from w[unknowns]; `cross` is the crossing
  /// state of the section that solves the block (BlockWorkspace::cross).
  void (*evaluate)(double* w, const int* cross);
  const char* description;    ///< for messages
  const double* nominal = nullptr;  ///< n scales |z_i| (> 0), or null: 1
  const double* lower = nullptr;    ///< n lower bounds (min), or null: none
  const double* upper = nullptr;    ///< n upper bounds (max), or null: none
};

/// Newton settings for nonlinear blocks.
struct NewtonOptions {
  int max_iterations = 50;        ///< Newton steps before giving up
  double step_tolerance = 1e-10;  ///< converged if |dz_i| <= tol·(1 + |z_i|) for all i
  double residual_tolerance = 1e-13;  ///< or if max |r_i| <= this
  int max_halvings = 12;          ///< line-search halvings of a step
};

struct SparseFactors;

/// Sparse LU factors of the linear blocks solved sparsely (size >=
/// kSparseBlockSize), per block: its pattern analysed once, the values last
/// factorised kept, so that the directional-derivative sweeps at one point
/// reuse them. A copy (a cloned model) starts empty.
class SparseFactorCache {
public:
  SparseFactorCache();
  ~SparseFactorCache();
  SparseFactorCache(const SparseFactorCache&);
  SparseFactorCache& operator=(const SparseFactorCache&);
  /// The factors of `block`, created empty on first use.
  SparseFactors& of(const LinearBlock& block);

private:
  std::unordered_map<const LinearBlock*, std::unique_ptr<SparseFactors>> blocks_;
};

/// Linear blocks of at least this many unknowns are solved by sparse LU
/// (Eigen's SparseLU, COLAMD ordering); smaller ones by dense LU with
/// partial pivoting, whose O(n²) work per solve is negligible there.
inline constexpr int kSparseBlockSize = 32;

/// Scratch and failure record of one model instance's block solves.
struct BlockWorkspace {
  std::vector<double> a, b, z, dz;  ///< matrix and vectors, resized as needed
  std::vector<double> scale;        ///< Newton: per-equation scale of the residual
  std::vector<int> pivots;          ///< row swaps
  /// Linear blocks: the last matrix factorised and its factors. A block whose
  /// matrix equals it (the same values, e.g. the mass matrix of the model's
  /// block again in each directional-derivative sweep at one point) reuses
  /// the factors: one factorisation per point instead of one per solve.
  std::vector<double> factored, lu;
  std::vector<int> lu_pivots;
  SparseFactorCache sparse;  ///< blocks of kSparseBlockSize unknowns or more
  double time = 0.0;                ///< model time of the current evaluation, for messages
  /// The crossing state of the section solving a nonlinear block, passed to
  /// its evaluate (relations inside a torn block's explicit part). Not a
  /// thread_local in the generated code: dynamic TLS in a dlopen()ed model
  /// costs a call per access and crashes LeakSanitizer's scan (glibc 2.36).
  const int* cross = nullptr;
  /// Per nonlinear block, its last solutions at increasing times: an
  /// evaluation at time t starts Newton from the latest one not after t.
  struct Solution {
    double time;
    std::vector<double> z;
  };
  std::unordered_map<const NonlinearBlock*, std::vector<Solution>> solutions;
  bool follow_time = true;  ///< false: Newton starts from w as it is, and the solutions are kept
  std::string failure;              ///< why the first failed block of this evaluation failed; empty if none
  /// Linear blocks found singular and solved by their minimum-norm solution
  /// (solve_linear), in the order first met; cleared by the model's reset.
  struct SingularSolves {
    const char* description;  ///< the block's
    long count;               ///< solves since the reset
    double earliest;          ///< the earliest model time of one
  };
  std::vector<SingularSolves> singular;
  DelayLines delays;                ///< the model's delay() histories (generated models with delays)
  NewtonOptions newton;             ///< settings
};

/// delay(e, T, Tmax) with a varying T: line `line` of ws.delays read at
/// ws.time − T; NaN, and the reason in ws.failure, for a T outside [0, Tmax].
double delay_value(BlockWorkspace& ws, std::size_t line, double delay_time);

/// Solves the linear block; writes z into w[unknowns] (with the factors of
/// ws.lu when J equals ws.factored, bit for bit). A singular J whose
/// equations are consistent (two stuck friction elements holding one shaft,
/// a term whose coefficient a parameter set to 0) leaves part of z
/// undetermined: the minimum-norm solution is taken (solve_minimum_norm, as
/// JModelica does) and counted in ws.singular. If they contradict each other,
/// sets the unknowns to NaN, records the failure in ws.failure (unless an
/// earlier block of the same evaluation failed first: that one is the
/// cause), returns false.
bool solve_linear(const LinearBlock& block, double* w, BlockWorkspace& ws);

/// One line per block of ws.singular: which block, how often, the earliest time.
std::vector<std::string> singular_notes(const BlockWorkspace& ws);

/// Solves the nonlinear block by damped Newton from w[unknowns], in units of
/// the unknowns' nominal values, keeping every iterate within [lower, upper]
/// (a start outside is moved inside). A one-unknown block Newton fails on is
/// solved by bracketing a sign change around the start and the Illinois
/// method (a limiter in a loop makes Newton cycle). On failure (singular J, non-finite
/// residuals, no convergence) sets the unknowns to NaN, records why (with the
/// last iterate) in ws.failure unless an earlier block failed first, and
/// returns false.
bool solve_nonlinear(const NonlinearBlock& block, double* w, BlockWorkspace& ws);

/// A generated Hessian's tables as printed (codegen/program.hpp, HessianCode):
/// the lower-triangle pattern (n×n CSC col_start/row_index), the colouring of
/// all n columns, and per product q its colours sigma[q] ≤ tau[q] and its entries
/// entry_start[q] .. entry_start[q+1]: row weight, slot of that row's second
/// derivative, pattern position.
struct HessianTablesView {
  int n = 0;
  const int* col_start = nullptr;
  const int* row_index = nullptr;
  const int* colour_start = nullptr;
  const int* colour_columns = nullptr;
  std::size_t products = 0;
  const int* sigma = nullptr;
  const int* tau = nullptr;
  const int* entry_start = nullptr;
  const int* entry_weight = nullptr;
  const int* entry_slot = nullptr;
  const int* entry_index = nullptr;
};

/// The products a Hessian evaluation runs, in the tables' layout (colours by
/// colour_start/colour_columns; products sorted by sigma, then tau).
struct HessianPlan {
  std::vector<int> colour_start{0}, colour_columns;
  std::vector<int> sigma, tau;
  std::vector<int> entry_start{0}, entry_weight, entry_slot, entry_index;
  std::size_t products() const { return sigma.size(); }
};

/// The products that give the entries whose row and column are both marked
/// in `columns` (all entries, as printed, if `columns` is empty). The marked
/// columns are coloured again so that no row's second derivative involves two
/// marked columns of one colour (greedy, in column order): each product then
/// still yields one tensor entry per row, and the unmarked columns, never
/// seeded, neither cost products nor add to any value. A design fixes the
/// model's parameters: its products run over the states and inputs alone.
void plan_hessian(const HessianTablesView& h, std::span<const std::uint8_t> columns, HessianPlan& out);

}  // namespace mo::runtime::generated
