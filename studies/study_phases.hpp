// Multi-phase collocation for studies on models with events (docs/events.md).
//
// A simulation of the initial guess gives the sequence of modes: between two
// events that change something (a reinit, a discrete variable, or a relation
// of the continuous equations) the model is smooth. Each mode becomes a phase
// on its own normalised time s ∈ [0, 1], t = τ_{k−1} + s·(τ_k − τ_{k−1}),
// with the relations and discrete variables frozen to the mode's values. All
// phases are stacked into one smooth OdeModel (states, inputs, algebraics and
// outputs copied per phase), so the existing collocation, its exact Jacobians
// and Hessians solve the multi-phase problem unchanged:
//
//   der_s(x^k) = (τ_k − τ_{k−1})·f_k(x^k, u^k, p, t_k(s)),
//   x^1(0) = x0(p),  x^{k+1}(0) = q^{k+1} (free parameters),
//   at s = 1 for k < K:  g_i(x^k, u^k, p, τ_k) = 0          (the indicator that switched)
//                        r(x^k, p, τ_k) − q^{k+1} = 0         (the jump; identity if no reinit)
//   τ_k − τ_{k−1} ≥ ε,  τ_k free in [t0, tf].
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mo/frontend/diagnostics.hpp"
#include "mo/frontend/flat.hpp"
#include "mo/runtime/estimate.hpp"
#include "mo/runtime/input.hpp"
#include "mo/runtime/model.hpp"
#include "mo/symbolic/ode.hpp"
#include "study.hpp"
#include "study_options.hpp"
#include "study_problem.hpp"

namespace mo::tools {

/// One mode: what is constant between two switches.
struct PhaseMode {
  std::vector<int> signs;        ///< per indicator: sign of g in the phase (±1; 0 if g stays 0)
  std::vector<double> discrete;  ///< the discrete variables d in the phase
  double start = 0.0, end = 0.0; ///< the phase's times in the simulation it came from
};

/// One switch between consecutive modes.
struct PhaseSwitch {
  double time = 0.0;                ///< the event time in the simulation
  /// A time event (sample() ticks): its time is fixed, it has no indicator
  /// (`indicator`, `direction` and `also` unused).
  bool timed = false;
  /// A timed switch's tick: the sample() (OdeModel::samples index) and k of
  /// τ = start + k·interval, if start and interval are parameter expressions
  /// (then τ moves with the parameters).
  std::optional<std::pair<std::size_t, double>> tick;
  std::size_t indicator = 0;        ///< the indicator that crossed
  int direction = 0;                ///< −1 downwards, +1 upwards
  /// Other indicators that crossed at the same instant, with their
  /// directions: their relations flip with the mode, their clauses fire here,
  /// but only `indicator` = 0 is imposed at the phase boundary (the others
  /// are taken to cross with it; the re-simulation checks that they do).
  std::vector<std::pair<std::size_t, int>> also;
  std::vector<std::size_t> whens;   ///< when-clauses that fired (OdeModel::whens indices)
  std::vector<double> states_after; ///< x⁺ in the simulation
};

/// The sequence of modes of one simulation: K modes, K − 1 switches.
struct ModeSequence {
  std::vector<PhaseMode> modes;
  std::vector<PhaseSwitch> switches;
  /// The when-clauses that fired at t0 (the event at initialisation, a
  /// sample() tick at t0), not the every-event ones.
  std::vector<std::size_t> initial_whens;
};

/// What the relations of a model are: which indicator each belongs to.
struct RelationMap {
  /// Per relation node of the continuous equations and when-conditions that
  /// has an indicator: (relation, indicator, its value after a downward crossing).
  struct Entry {
    symbolic::Expr relation;
    std::size_t indicator;
    double value_if_down;
  };
  std::vector<Entry> entries;
  std::vector<bool> in_equations;  ///< per indicator: a relation of it is in the steps/outputs
  /// Per discrete variable: a held value, one that a when-clause sets from
  /// the continuous part (symbolic::discrete_with_tangents: a sample-and-hold
  /// of a state, a latched input). Each phase has it as an unknown, tied to
  /// the value of the clause that sets it at a boundary (docs/events.md).
  std::vector<bool> held;
  /// True if some discrete variable is held.
  [[nodiscard]] bool holds_values() const { return std::find(held.begin(), held.end(), true) != held.end(); }
};

/// The relations of `ode` matched to its zero crossings (adds differences to its arena).
RelationMap match_relations(symbolic::OdeModel& ode);

/// The leaves that `roots` read through the steps of `ode`: those of the
/// steps that compute the algebraic variables and derivatives they read, and
/// so on (not the roots' own leaves).
std::vector<symbolic::Expr> leaves_through_steps(const symbolic::OdeModel& ode, const std::vector<symbolic::Expr>& roots);

/// A reason the multi-phase formulation cannot take a model or a sequence,
/// with the when-clause (index) or indicator it concerns.
struct PhaseRefusal {
  std::string message;
  std::optional<std::size_t> when;       ///< the when-clause concerned
  std::optional<std::size_t> indicator;  ///< else the indicator concerned
};

/// Checks the model's event constructs once: every when-condition a single
/// relation with an indicator or one that changes at time events only (over
/// sample(), initial(), discrete variables and parameters); reinit values
/// over states, parameters, time, pre() and discrete variables only (no
/// algebraic unknowns); a held value reading no other held value but pre()
/// and its own clause's (through the equations neither); no relation of the
/// equations on an input. nullopt if all hold.
std::optional<PhaseRefusal> check_event_constructs(const symbolic::OdeModel& ode, const RelationMap& rel);

/// Simulates `model` from t0 to tf with `inputs` and `p`, recording every
/// event, and returns its mode sequence, or a refusal (a state event whose
/// event iteration changes more, more than `max_switches` state-event
/// switches or kMaxTimedSwitches time events, two switches closer than
/// `min_gap`, a held value set twice at t0 from its pre()). Several
/// indicators crossing at one instant make one switch (the first of them its
/// `indicator`, the others `also`); a time event that changes the model is a
/// timed switch.
/// `simulation_message` is set if the simulation itself failed.
/// More time events that change the model in one simulation are refused:
/// each is a phase of the stacked model.
constexpr std::size_t kMaxTimedSwitches = 1000;
struct ModeRecording {
  std::optional<ModeSequence> sequence;
  std::optional<PhaseRefusal> refusal;
  std::string simulation_failure;  ///< non-empty if the simulation failed
};
ModeRecording record_modes(const runtime::Model& model, const symbolic::OdeModel& ode, const RelationMap& rel,
                           const runtime::Inputs& inputs, const std::vector<double>& p, double t0, double tf,
                           std::size_t max_switches, double min_gap);

/// True if the two sequences have the same switches (indicator, direction,
/// clauses; a timed switch its tick, else its time) and modes (signs of the indicators of
/// the equations, discrete values but the held ones).
bool same_modes(const ModeSequence& a, const ModeSequence& b, const RelationMap& rel);

/// A boundary between consecutive phases: a switch of the sequence (free
/// time, indicator = 0, jump; a timed switch at its fixed time, jump) or a
/// fixed cut (a measurement time; continuity).
struct PhaseBoundary {
  double time = 0.0;                        ///< the (guessed) time
  std::optional<std::size_t> switch_index;  ///< the switch, or nullopt for a fixed cut
  std::vector<double> states_after;         ///< guess of the next phase's start
};

/// Phases in time order: per phase the mode it is in, and the boundaries between them.
struct PhaseLayout {
  std::vector<std::size_t> mode;         ///< per phase: index into ModeSequence::modes
  std::vector<PhaseBoundary> boundaries; ///< phases − 1
};

/// One phase per mode, boundaries at the switches.
PhaseLayout phase_layout(const ModeSequence& seq);


/// The stacked model of a mode sequence and where its parts are.
struct PhasedModel {
  symbolic::OdeModel ode;
  std::size_t phases = 1;
  PhaseLayout layout;                          ///< what it was built from
  std::size_t nx = 0, nu = 0, np = 0, ny = 0;  ///< sizes of the base model
  std::vector<std::size_t> switch_time;        ///< parameter index of τ_k, per switch (fixed if timed)
  std::vector<bool> timed_switch;              ///< per switch: a time event (PhaseSwitch::timed)
  /// Per switch: a timed switch's τ = start + k·interval over the
  /// parameters (PhaseSwitch::tick), else an invalid Expr.
  std::vector<symbolic::Expr> tick_time;
  std::vector<std::size_t> phase_start;        ///< first parameter index of q^{k+1}, per boundary
  std::vector<std::size_t> indicator_output;   ///< output index of g, per switch
  std::vector<std::size_t> jump_output;        ///< first of nx output indices, per boundary
  std::vector<std::size_t> length_output;      ///< output index of τ_k − τ_{k−1}, per phase
  /// The held values' unknowns (parameters; RelationMap::held): one per held
  /// variable that a clause sets at t0 or at a boundary, with its guess.
  std::vector<std::size_t> held_parameter;
  /// Outputs zero at s = 1 of the phase before a boundary: the value a fired
  /// clause assigns minus the next phase's unknown; `held_initial_output`
  /// likewise at s = 0 of the first phase for the clauses fired at t0.
  std::vector<std::size_t> held_output;
  std::vector<std::size_t> held_initial_output;
  /// A control read by a held value at a timed switch is continuous there:
  /// parameter ψ, outputs u^k − ψ (zero at s = 1 of phase k) and u^{k+1} − ψ
  /// (zero at s = 0 of phase k + 1).
  struct Continuity {
    std::size_t input, parameter, before_output, after_output;
  };
  std::vector<Continuity> continuity;
  std::optional<std::size_t> lagrange_output;  ///< Σ_k (τ_k − τ_{k−1})·L^k
  /// With sensitivity states: per switch, the first of nb parameters φ = f⁺
  /// (the base states' derivatives just after it) and the first of nb outputs
  /// der(x^{k+1}) − φ, zero at s = 0 of the next phase (docs/events.md).
  std::vector<std::size_t> fplus_parameter, fplus_output;
  /// With sensitivity states: per switch, the first of nu parameters ψ and of
  /// nu outputs u^k − ψ (zero at s = 1) and u^{k+1} − ψ (zero at s = 0): the
  /// input is continuous at a switch, so that the jump's f⁻ and f⁺ see the
  /// same input and the sensitivities hold for the input on physical time.
  std::vector<std::size_t> input_parameter, input_before_output, input_after_output;
  /// Per phase and indicator of the equations with a sign in that mode: the
  /// output sign·g, ≥ 0 keeps the phase in its mode (used by design).
  std::vector<std::size_t> sign_output;
  /// Index of phase k's copy of base state i / input j / output o.
  [[nodiscard]] std::size_t state(std::size_t k, std::size_t i) const { return k * nx + i; }
  [[nodiscard]] std::size_t input(std::size_t k, std::size_t j) const { return k * nu + j; }
  [[nodiscard]] std::size_t output(std::size_t k, std::size_t o) const { return k * ny + o; }
};

/// The time a phase of `pm` that ends at `b` ends at if that is fixed (a
/// cut or a timed switch), else NaN.
double fixed_end_time(const PhasedModel& pm, const PhaseBoundary& b);

/// Stacks the phases of `layout` (modes from `seq`) for `base` on [t0, tf];
/// `lagrange` is the base output index of the objective integrand, if any.
PhasedModel build_phased_model(symbolic::OdeModel& base, const RelationMap& rel, const ModeSequence& seq,
                               const PhaseLayout& layout, double t0, double tf, std::optional<std::size_t> lagrange);

/// s ↦ signal(t0 + s·(t1 − t0)): a physical-time signal seen on a phase's normalised time.
std::unique_ptr<runtime::InputSignal> phase_time_signal(std::shared_ptr<const runtime::InputSignal> signal,
                                                        double t0, double t1);

/// Task optimal_control on a model with events: the multi-phase collocation,
/// re-simulation and mode-sequence check (up to 3 rebuilds); writes the
/// results in physical time with `status` saying whether the check held.
/// `ode` is the lowered model with the problem's outputs. Returns the exit status.
int optimal_control_with_events(frontend::flat::Model& flat, const StudyCli& cli, StudyOptions opt,
                                ProblemOutputs problem, symbolic::OdeModel& ode,
                                frontend::DiagnosticEngine& diags);

/// The study's model lowered again (measured outputs as `ode` has them) with
/// sensitivity states for the named parameters.
using Relower = std::function<symbolic::OdeModel(const std::vector<std::string>& parameters)>;

/// Task estimation on a model with events: one experiment without inputs,
/// phases cut at every sample time (docs/events.md); statistics from CVODES
/// sensitivities through the events, or with held values from the model
/// `relower` gives. Returns the exit status.
int estimation_with_events(frontend::flat::Model& flat, const StudyCli& cli, StudyOptions opt,
                           ProblemOutputs problem, symbolic::OdeModel& ode, frontend::DiagnosticEngine& diags,
                           const Relower& relower);

/// A multi-phase estimation (without writing anything): the estimate with
/// its statistics (CVODES sensitivities through the events, or those of
/// `with_states`, compiled with sensitivity states for e's parameters), `status` and
/// `events` as summary.json has them, or a refusal or an error.
struct PhasedEstimate {
  runtime::EstimationResult result;  ///< status not success/acceptable if the events check failed
  std::string status;
  nlohmann::json events;
  std::optional<PhaseRefusal> refusal;
  std::string error;
};

/// Estimates e's free parameters from its one experiment (no inputs) on the
/// model `model` compiled from `ode`, by the multi-phase collocation.
PhasedEstimate phased_estimate(const runtime::Model& model, symbolic::OdeModel& ode, const RelationMap& rel,
                               const runtime::EstimationProblem& e, const StudyCli& cli,
                               const runtime::Model* with_states = nullptr);

/// Task monte_carlo on a model with events: each run's estimate by
/// phased_estimate (cases without inputs). Returns the exit status.
int monte_carlo_with_events(frontend::flat::Model& flat, const StudyCli& cli, StudyOptions opt,
                            ProblemOutputs problem, symbolic::OdeModel& ode, frontend::DiagnosticEngine& diags);

/// Task design on a model with events: phases at the switches and cut at the
/// measurement times, the sensitivity states jumping at the switches, the
/// Fisher matrix of the collocated sensitivities; re-simulated through the
/// events (mode sequence, states, Fisher matrix), rebuilt up to 3 times.
/// Returns the exit status.
int design_with_events(frontend::flat::Model& flat, const StudyCli& cli, StudyOptions opt, ProblemOutputs problem,
                       symbolic::OdeModel& ode, frontend::DiagnosticEngine& diags);

}  // namespace mo::tools
