// Tearing of nonlinear equation blocks (Cellier's heuristic, as OpenModelica's
// omcTearing applies it), so that Newton iterates on a few tearing variables
// and every other unknown of the block is computed from them explicitly.
//
//   block   0 = r_i(z_1..z_n)                     (BLT block, nonlinear)
//   torn    z_T   tearing (iteration) variables, guessed at their start values
//           z_k := e_k(z_T, w)                   for the others, in causal order:
//                                                r_i affine in z_k with a
//                                                coefficient over parameters only
//           0 = r_j(z_T, e(z_T, w))              the torn equations, one per z_T
//
// The steps are the block over z_T (its residuals with every z_k substituted,
// so its Jacobian is the total derivative) followed by the assignments z_k :=
// e_k, also written over z_T: downstream (directional derivatives, code
// generation, the interpreter, event indicators) sees ordinary steps.
//
// Choice of the tearing variables, repeated until the torn residuals are
// finite at the start point (every leaf at its start value, time 0, inputs 0)
// or eight tries: (0) while an unknown whose start the author gave is left,
// only those (as Dymola reads it: a start value is the author's guess for an
// iteration variable; the MSL's Schmitt trigger gives `r2.i(start = Vps/R2)`
// so that Newton finds the saturated solution, not the unstable one at 0).
// The author is who modifies a component, not its class: a start in the
// declaring class (PartialCompliant's `s_rel(start = 0)`) is that class's
// default for every use unless the user makes it an initial value (a joint's
// `phi(fixed = true)`); preferring such defaults made the MSL's ThreeSprings
// iterate on three spring lengths at 0 besides the joint position its
// author started;
// (1) the equations with the most unknowns left; (2) among their variables,
// those in most remaining equations; (3) among those, the one after which
// most equations become solvable for their last unknown. Then each chosen
// variable without the author's start, the latest first, is dropped when the
// others still make every unknown explicit (the greedy order tears a spring's
// length before the joint position it follows from).
// A try whose torn residuals are not finite (a guess of 0 that makes a
// thermal voltage 0 and `v/vt` 0/0) marks its tearing variables "avoid" and
// tries again; a variable to avoid is chosen only when no other remains.
#pragma once

#include <string>
#include <vector>

#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/ode.hpp"

namespace mo::symbolic::detail {

/// One BLT block as the caller found it.
struct BlockEquations {
  std::vector<Expr> residuals;       ///< 0 = residuals[i]
  std::vector<Expr> unknowns;        ///< matched to the residuals, same length
  std::vector<double> start;         ///< first Newton guess per unknown
  std::vector<std::string> origins;  ///< per residual, may be empty strings
  /// Per unknown: the model's author gave its start (a modification from
  /// outside the class that declares it, or a variable of the model's own:
  /// DaeVar::start_guess); preferred as tearing variable. Empty means none.
  std::vector<char> start_guess;
};

/// Which variables tearing chose (indices into BlockEquations).
struct Tearing {
  std::vector<std::size_t> iteration;     ///< tearing variables, in order of choice
  std::vector<std::size_t> residual_eqs;  ///< torn equations (Newton's residuals)
  std::vector<std::pair<std::size_t, std::size_t>> causal;  ///< (equation, unknown) solved explicitly, in order
};

/// The tearing of `block` (nonlinear, two or more unknowns). `at_start` holds
/// the values of the leaves outside the block at the start point; a leaf it
/// lacks makes the finiteness test inconclusive (the first try is kept).
Tearing choose_tearing(ExprArena& arena, const BlockEquations& block, const LeafValues& at_start);

/// The steps computing the block's unknowns: solve_block's single step for a
/// linear block, a scalar block, or a nonlinear block tearing leaves whole
/// (no equation solvable explicitly, or `tear` false); otherwise the torn
/// block followed by the explicit assignments. Origins are filled in.
std::vector<Step> solve_block_torn(ExprArena& arena, const BlockEquations& block,
                                   const LeafValues& at_start, bool tear);

}  // namespace mo::symbolic::detail
