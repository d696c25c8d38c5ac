// The starts of a multistart design: the listed signals of the `starts`
// option (or the problem's own initial guess), then `starts = N` random ones.
//
// A random start draws, for every free input and every control interval (an
// element, or a block of `blocking_factors` elements), one value uniformly
// within the input's [min, max]: the same piecewise-constant shape the
// optimiser chooses, so every point of the box of controls can be drawn and
// no shape (smooth, slow, symmetric) is favoured. Start r (0-based) of seed K
// uses its own generator, a mt19937_64 seeded by std::seed_seq{K, r}, and
// maps each 64-bit draw to [0, 1) by its top 53 bits: a start's values depend
// on K and r only (not on how many starts there are, nor on the platform's
// distributions), so results are reproducible.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "mo/runtime/optimize.hpp"
#include "study_options.hpp"

namespace mo::tools {

/// One start: where it comes from and the initial guess of every control.
struct DesignStart {
  std::string origin;  ///< "initial_guess", "listed" or "random"
  std::string label;   ///< the signal as written, or "random r (seed K)"
  /// Per control of the problem, in order: its initial guess (null: the control's own).
  std::vector<std::shared_ptr<const runtime::InputSignal>> guesses;
};

/// Start times of the control intervals of `c` on [t0, tf] (the element grid,
/// grouped by blocking factors), the first at t0.
std::vector<double> control_interval_times(const runtime::OptimalControlProblem& ocp,
                                           const runtime::FreeControl& c);

/// Random start r of seed K for every control of `ocp` (see above). Throws
/// UsageError naming an input whose bounds are not finite.
DesignStart random_start(const runtime::OptimalControlProblem& ocp, const runtime::ModelInfo& info,
                         int seed, std::size_t r);

/// The starts the options ask for, in order: each signal of `starts` for the
/// first control (or, without any, the problem's own guess), then
/// `random_starts` random ones.
std::vector<DesignStart> design_starts(const StudyOptions& o, const runtime::OptimalControlProblem& ocp,
                                       const runtime::ModelInfo& info);

}  // namespace mo::tools
