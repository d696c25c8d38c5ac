// Pieces shared by the multi-phase tasks (study_phases.cpp, study_phases_estimation.cpp).
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mo/runtime/optimize.hpp"
#include "multistart.hpp"
#include "study_phases.hpp"

namespace mo::tools {

/// The current guess on physical time: all base parameters, one signal per control.
struct Guess {
  std::vector<double> parameters;
  std::vector<std::shared_ptr<const runtime::InputSignal>> controls;
};

constexpr std::size_t kMaxSwitches = 20;  ///< more switches in one simulation: chattering or Zeno
constexpr int kMaxAttempts = 3;           ///< solves with an updated mode sequence
/// The re-simulation must agree with the collocation to this fraction of each
/// state's scale (its largest |x| on the trajectory, at least its nominal).
constexpr double kStateTolerance = 1e-3;
/// A re-simulated switch must lie this fraction of the horizon from the collocation's.
constexpr double kTimeTolerance = 1e-3;

/// The initial guess of `P`: free parameters' and controls' initialGuess
/// (a control without one: 0 clamped to its bounds).
Guess initial_guess(const runtime::OptimalControlProblem& P);

/// The inputs of `P` under the guess: its fixed inputs and the guessed controls.
runtime::Inputs guess_inputs(const Guess& g, const runtime::OptimalControlProblem& P, std::size_t nu);

/// Phases cut at every sample time inside (t0, tf), modes from `seq`; the
/// next phase's start guesses from a simulation at those times with
/// `inputs`. nullopt with `why` if a switch lies on a sample time or the
/// simulation fails.
std::optional<PhaseLayout> sample_layout(const runtime::Model& model, const ModeSequence& seq,
                                         const std::vector<double>& samples, const runtime::Inputs& inputs,
                                         const std::vector<double>& p, double t0, double tf, double min_gap,
                                         std::string& why);

/// Per switch: how many sample cuts precede it (the interval it must stay in).
std::vector<std::size_t> interleaving(const ModeSequence& seq, const std::vector<double>& samples, double t0);

/// Switches that ended within `near` of a sample time (their phase's length
/// bound active), with a new guess in the middle of the sample interval
/// across it; not the timed ones (on a sample time by design).
std::map<std::size_t, double> stuck_switches(const std::vector<double>& switches, const std::vector<bool>& timed,
                                             const std::vector<double>& samples, double t0, double tf, double near);

/// The phase of `ends` (fixed_end_time() per boundary) that ends at `t`,
/// within rounding (a tick start + k·interval against a sample time of a
/// file), or ends.end().
inline std::vector<double>::const_iterator phase_ending_at(const std::vector<double>& ends, double t) {
  return std::find_if(ends.begin(), ends.end(),
                      [&](double e) { return std::abs(e - t) <= 1e-12 * std::max(1.0, std::abs(t)); });
}

/// The multi-phase problem on s ∈ [0, 1] for the stacked model `pm` built from
/// `P` (the base problem on physical time): controls and fixed inputs per
/// phase, free switching times and phase starts, switch and jump constraints
/// at s = 1, phase lengths ≥ min_gap. Throws UsageError for point constraints
/// inside the horizon.
runtime::OptimalControlProblem phased_problem(const runtime::OptimalControlProblem& P, const PhasedModel& pm,
                                              const ModeSequence& seq, const Guess& g,
                                              const runtime::ModelInfo& base, double min_gap,
                                              bool keep_signs = false);

/// The phases' boundaries τ_0 = t0 < ... < τ_K = tf at the solution `r`.
std::vector<double> boundary_times(const PhasedModel& pm, const runtime::OptimizationResult& r, double t0, double tf);

/// The switching times at the solution, one per switch.
std::vector<double> solved_switch_times(const PhasedModel& pm, const runtime::OptimizationResult& r);

/// The solution on physical time for the base model (names, element times, controls).
runtime::OptimizationResult physical_result(const PhasedModel& pm, const runtime::OptimizationResult& r,
                                            const std::vector<double>& taus, const runtime::ModelInfo& base,
                                            std::size_t num_controls);

/// The re-simulation of the base model at the optimum against the collocation.
struct EventCheck {
  std::optional<ModeSequence> modes;  ///< the re-simulation's mode sequence
  std::string failure;                ///< why there is none
  bool same_modes = false;            ///< same_modes() with the solved sequence
  double max_relative = 0.0;          ///< largest state difference / the state's scale
  double max_switch_shift = 0.0;      ///< largest |τ_sim − τ_coll|
};

/// Re-simulates `model` with the inputs and parameters of `R` (fills R.check)
/// and compares modes, switching times and states away from the switches.
EventCheck check_resimulation(runtime::Model& model, const symbolic::OdeModel& ode, const RelationMap& rel,
                              const ModeSequence& seq, const runtime::OptimalControlProblem& Pphys,
                              runtime::OptimizationResult& R, const std::vector<double>& switches, double min_gap);

/// "h falls through 0 at t = 0.45, ..." for messages.
std::string describe_modes(const symbolic::OdeModel& ode, const ModeSequence& seq);

/// summary.json's `status`: Ipopt's, or resimulation_failed, mode_sequence_changed, resimulation_mismatch.
std::string event_status(const runtime::OptimizationResult& R, const EventCheck& check, bool same, double time_tol,
                         double state_tol);

/// summary.json's `events` object.
nlohmann::json events_json(const symbolic::OdeModel& ode, const ModeSequence& seq, const EventCheck& check,
                           std::size_t phases, int attempt, const std::vector<double>& switches, bool same,
                           double time_tol, double state_tol);

/// Reports `r` at its when-clause (or the first switching construct) and prints the diagnostics; returns 1.
/// How one start of a multi-phase design ended.
struct EventDesignRun {
  runtime::InputDesignResult result;  ///< on physical time (Pphys's grid)
  std::string status;                 ///< event_status(), "switch_at_sample_time", or empty with `error`
  nlohmann::json events;              ///< summary.json's "events"
  std::optional<PhaseRefusal> refusal;  ///< the guess's simulation cannot be cut into phases
  std::string error;                    ///< the guess's simulation or layout failed
};

/// The multistart of a multi-phase design (issue 11's multistart on a model
/// with events): `solve(k, log_file, isolated)` solves start k (its own mode
/// sequence from its own guess) on the parallel runner; a start converged when
/// its status is success or acceptable with a finite criterion. Returns the
/// starts, their local optima (cluster_optima) and, in `best`, the best
/// converged start's run (else the first start that has a result). nullopt on
/// MPI ranks other than 0. If no start has a result, `best.error` says so
/// (with start 1's reason) and the starts' table is returned all the same.
std::optional<MultistartResult> event_design_multistart(
    const std::vector<DesignStart>& starts, const MultistartSettings& settings,
    const std::function<EventDesignRun(std::size_t k, const std::string& log_file, bool isolated)>& solve,
    EventDesignRun& best);

int refuse_phases(const frontend::flat::Model& flat, const PhaseRefusal& r, frontend::DiagnosticEngine& diags);

}  // namespace mo::tools
