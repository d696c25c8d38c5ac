// The runtime model interface: what generated code implements.
//
//   der(x) = f(x, u, p, t)            states x ∈ R^nx, inputs u ∈ R^nu,
//   y      = h(x, u, p, t)            outputs y ∈ R^ny, parameters p ∈ R^np,
//   x(t0)  = x0(p)                    start values may depend on parameters,
//
// with event indicators g(t, x, u, p) ∈ R^ng: when g_i crosses zero (or a time
// event is reached) the model's event handler may change its discrete
// variables d and reinitialise states (Modelica when/reinit/pre). Between
// events d is constant and f, h may depend on it.
//
// Derivatives, each with its sparsity and its values as separate entry points:
//   Jacobians  ∂f/∂x, ∂f/∂u, ∂f/∂p, ∂h/∂x, ∂h/∂u, ∂h/∂p, ∂x0/∂p,
//   Hessians   ∇²_z (λᵀ f) and ∇²_z (μᵀ h), z = (x, u, p), lower triangle.
//
// Some states may themselves be forward sensitivities S = ∂x_i/∂p_j that the
// compiler appended (der(S) = f_x S + f_p); their metadata says so.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mo::runtime {

/// A sparsity pattern in compressed sparse column (CSC) form.
/// Column j holds entries row_index[col_start[j]] .. row_index[col_start[j+1]-1],
/// rows strictly ascending; value arrays use the same entry order.
struct Sparsity {
  int rows = 0;                ///< number of rows
  int cols = 0;                ///< number of columns
  std::vector<int> col_start;  ///< size cols + 1, col_start[0] = 0
  std::vector<int> row_index;  ///< size nnz()

  /// Number of structural nonzeros.
  [[nodiscard]] int nnz() const { return static_cast<int>(row_index.size()); }
  /// The pattern with no entries (rows × cols); a zero derivative.
  static Sparsity empty(int rows, int cols);
  /// The fully dense pattern (rows × cols), column by column.
  static Sparsity dense(int rows, int cols);
  /// Builds a pattern from (row, col) pairs in any order; duplicates are merged.
  /// Throws std::invalid_argument if a pair lies outside rows × cols.
  static Sparsity from_triplets(int rows, int cols,
                                std::span<const std::pair<int, int>> entries);
  /// True if col_start/row_index are consistent (sizes, bounds, ascending rows).
  [[nodiscard]] bool is_valid() const;
  /// Index of entry (row, col) in the value array, or -1 if structurally zero.
  [[nodiscard]] int find(int row, int col) const;
};

/// A derivative block; the name says function and argument (f_x = ∂f/∂x).
/// Sizes: f_* have nx rows, h_* have ny rows, x0_p is nx × np; *_x has nx
/// columns, *_u nu, *_p np.
enum class Jacobian { f_x, f_u, f_p, h_x, h_u, h_p, x0_p };

/// Which contraction a Hessian block belongs to: Σ λ_i f_i or Σ μ_i h_i.
enum class Hessian { f, h };

/// Forward sensitivity bookkeeping of a state that is S = ∂x_state/∂p_parameter.
struct SensitivityOf {
  std::size_t state;      ///< index of the base state x_i
  std::size_t parameter;  ///< index of the parameter p_j
};

/// A discrete sensitivity: discrete variable `index` holds ∂d/∂p of discrete
/// variable `discrete` (a sample-and-hold of a state, say), constant between
/// events; the simulator sets it at each event (docs/events.md).
struct DiscreteSensitivity {
  std::size_t index;      ///< the discrete variable that holds the sensitivity
  std::size_t discrete;   ///< index of the discrete variable d
  std::size_t parameter;  ///< index of the parameter p_j
};

/// A named scalar of the model, as the modeller declared it.
struct Variable {
  std::string name;         ///< Modelica name, e.g. "pendulum.phi" or "d(phi)/d(m2)"
  std::string description;  ///< the declaration's comment string, may be empty
  std::string unit;         ///< SI unit string, e.g. "m/s", may be empty
};

/// A state with its start/nominal/bounds attributes.
struct StateVariable : Variable {
  double start = 0.0;    ///< start value at the default parameters (x0 is authoritative)
  double nominal = 1.0;  ///< magnitude used for scaling and absolute tolerances, > 0
  double min = -std::numeric_limits<double>::infinity();  ///< lower bound
  double max = std::numeric_limits<double>::infinity();   ///< upper bound
  std::optional<SensitivityOf> sensitivity;  ///< set iff this is a sensitivity state
};

/// A parameter with its default value.
struct Parameter : Variable {
  double value = 0.0;  ///< default value
  double min = -std::numeric_limits<double>::infinity();  ///< lower bound
  double max = std::numeric_limits<double>::infinity();   ///< upper bound
};

/// Everything about a model that does not need evaluation.
struct ModelInfo {
  std::string name;                    ///< model class name
  std::vector<StateVariable> states;   ///< x, sensitivity states last by convention
  std::vector<Variable> inputs;        ///< u
  std::vector<Variable> outputs;       ///< y
  std::vector<Parameter> parameters;   ///< p
  std::vector<Variable> discrete;      ///< d (Real, Integer and Boolean alike, as double)
  /// The discrete variables that are sensitivities of others; empty unless
  /// the model was compiled with sensitivities and has a when-clause value
  /// that moves with a parameter.
  std::vector<DiscreteSensitivity> discrete_sensitivities;
  std::size_t num_event_indicators = 0;  ///< ng
  /// Per indicator: false if no relation on it enters the right-hand side
  /// (it only feeds when-conditions and discrete equations); empty: all do.
  std::vector<bool> indicator_in_rhs;
  /// Per indicator: g as Modelica text (`x - y` for the relation x > y), for
  /// diagnostics; empty (or an empty text): not known.
  std::vector<std::string> indicator_text;
  /// Per input: true if the initial system (the start values) reads it, so
  /// that x0 depends on u(t0); empty: none does.
  std::vector<bool> input_in_initial;
  /// Number of delay() calls: each keeps a history of its expression that
  /// the simulator fills (Model::record_delays). Collocation cannot express
  /// them and refuses such a model.
  std::size_t num_delays = 0;

  /// Index of the state named `name`, or nullopt.
  [[nodiscard]] std::optional<std::size_t> state_index(std::string_view name) const;
  /// Index of the input named `name`, or nullopt.
  [[nodiscard]] std::optional<std::size_t> input_index(std::string_view name) const;
  /// Index of the output named `name`, or nullopt.
  [[nodiscard]] std::optional<std::size_t> output_index(std::string_view name) const;
  /// Index of the parameter named `name`, or nullopt.
  [[nodiscard]] std::optional<std::size_t> parameter_index(std::string_view name) const;
  /// Default parameter values, in order.
  [[nodiscard]] std::vector<double> default_parameters() const;
  /// Number of states that are not sensitivity states (the base system).
  [[nodiscard]] std::size_t num_base_states() const;
};

/// What the simulator tells the event handler about why it is called.
struct EventCause {
  double t = 0.0;  ///< event time
  /// Per indicator: -1 crossed downwards, +1 upwards, 0 did not cross; -2/+2
  /// left downwards/upwards a value of exactly 0 that it was held at since the
  /// integration restarted (it did not change sign). Empty (all zero) for time
  /// events and for event-iteration repeats. At the event point g_i ≈ 0, so
  /// relations on g_i must take their value from the direction's sign.
  std::span<const int> crossings;
  bool time_event = false;  ///< the time from next_time_event() was reached
};

/// What the event handler did.
struct EventResponse {
  bool discrete_changed = false;  ///< some d changed: the simulator iterates the handler
  bool states_reinit = false;     ///< some x were reinitialised: the integrator restarts
  bool terminate = false;         ///< terminate() was called: simulation ends here
  std::string message;            ///< terminate()'s text
};

/// One direction along which the event map is differentiated: the derivative
/// of (x, p, t) at the event instant, of the inputs (u̇ δt as the event time
/// moves) and of the discrete variables that have discrete sensitivities.
/// handle_event_tangent() updates `x` and `d`.
struct EventTangent {
  std::span<double> x;         ///< δx, nx values; on return δx after the handler call
  std::span<const double> p;   ///< δp, np values
  double t = 0.0;              ///< δt (the event time's derivative)
  /// δd, nd values (or empty: all 0). Read and updated only for the discrete
  /// variables d of ModelInfo::discrete_sensitivities; 0 for the others.
  std::span<double> d = {};
  std::span<const double> u = {};  ///< δu, nu values (or empty: all 0)
};

/// A model compiled to C++: generated code derives from this class.
///
/// Threading: an instance owns its scratch (work slots) and its discrete
/// variables, so evaluation functions are non-const and an instance must be
/// used by one thread at a time; clone() gives an independent instance for
/// another thread. Metadata accessors are const and may be shared.
///
/// Array arguments have the sizes given by info(); the functions do not check
/// them. Evaluation never throws; a non-finite result (e.g. division by zero)
/// is reported by the caller that sees it.
class Model {
public:
  /// Generated models are owned through Model pointers.
  virtual ~Model() = default;

  /// Names, units, attributes and sizes; the same object for the model's life.
  [[nodiscard]] virtual const ModelInfo& info() const = 0;
  /// A fresh, independent instance in the initial discrete state.
  [[nodiscard]] virtual std::unique_ptr<Model> clone() const = 0;

  // --- continuous part -------------------------------------------------------

  /// x0 = x0(p, u0, t0): the initial system solved at time t0 with the inputs
  /// at their values u0 there (nu values, or empty for all 0: the start
  /// values of a model whose initial system reads no input, such as
  /// `initial equation der(x) = 0` under `der(x) = -x + u`, depend on p
  /// alone); also resets the discrete variables to their start values and
  /// runs the event at initialisation at t0.
  virtual void initial_state(double t0, std::span<const double> u0, std::span<const double> p,
                             std::span<double> x0) = 0;
  /// initial_state(0, {}, p, x0): t0 = 0 and every input 0.
  void initial_state(std::span<const double> p, std::span<double> x0) { initial_state(0.0, {}, p, x0); }
  /// xdot = f(x, u, p, t) for the current discrete variables.
  virtual void rhs(double t, std::span<const double> x, std::span<const double> u,
                   std::span<const double> p, std::span<double> xdot) = 0;
  /// y = h(x, u, p, t) for the current discrete variables.
  virtual void outputs(double t, std::span<const double> x, std::span<const double> u,
                       std::span<const double> p, std::span<double> y) = 0;

  // --- derivatives -------------------------------------------------------------

  /// Sparsity of a Jacobian block (CSC); constant over the model's life.
  [[nodiscard]] virtual const Sparsity& jacobian_sparsity(Jacobian block) const = 0;
  /// Values of a Jacobian block in jacobian_sparsity(block) order, nnz of them.
  /// For Jacobian::x0_p, x is ignored and (t, u) is the initial point (t0,
  /// u0) of initial_state(); an empty u means all 0.
  virtual void jacobian_values(Jacobian block, double t, std::span<const double> x,
                               std::span<const double> u, std::span<const double> p,
                               std::span<double> values) = 0;

  /// True if hessian_sparsity/hessian_values are implemented for `which`;
  /// if false, optimisers fall back to a limited-memory approximation.
  [[nodiscard]] virtual bool provides_hessian(Hessian which) const {
    (void)which;
    return false;
  }
  /// Lower triangle (row ≥ col) of ∇²_z(λᵀf) or ∇²_z(μᵀh), z = (x, u, p), as a
  /// (nx+nu+np)² CSC pattern. Throws std::logic_error (an internal error) unless
  /// provides_hessian(which).
  [[nodiscard]] virtual const Sparsity& hessian_sparsity(Hessian which) const;
  /// Values of that Hessian for multipliers `weights` (size nx for f, ny for h).
  /// Throws std::logic_error (an internal error) unless provides_hessian(which).
  virtual void hessian_values(Hessian which, double t, std::span<const double> x,
                              std::span<const double> u, std::span<const double> p,
                              std::span<const double> weights, std::span<double> values);
  /// hessian_values where only the entries whose row and column are both
  /// marked in `columns` (one flag per z = (x, u, p) column) are wanted; the
  /// others may be left 0. A collocation NLP wants no column of a parameter
  /// it does not estimate: the generated code then skips the directional
  /// derivatives of those entries. The default computes them all.
  virtual void hessian_values_for(std::span<const std::uint8_t> columns, Hessian which, double t,
                                  std::span<const double> x, std::span<const double> u,
                                  std::span<const double> p, std::span<const double> weights,
                                  std::span<double> values) {
    (void)columns;
    hessian_values(which, t, x, u, p, weights, values);
  }

  // --- events ------------------------------------------------------------------

  /// g(t, x, u, p), info().num_event_indicators values; a sign change is an event.
  virtual void event_indicators(double t, std::span<const double> x,
                                std::span<const double> u, std::span<const double> p,
                                std::span<double> g) {
    (void)t, (void)x, (void)u, (void)p, (void)g;
  }
  /// The first time event strictly after t, or +infinity if there is none.
  [[nodiscard]] virtual double next_time_event(double t) const {
    (void)t;
    return std::numeric_limits<double>::infinity();
  }
  /// Handles an event at cause.t: saves pre(d) := d, evaluates the active
  /// when-clauses, and may set d and reinit x in place. The simulator calls it
  /// again (with no crossings) while discrete_changed, up to a limit.
  virtual EventResponse handle_event(const EventCause& cause, std::span<double> x,
                                     std::span<const double> u, std::span<const double> p) {
    (void)cause, (void)x, (void)u, (void)p;
    return {};
  }
  // --- derivatives through events (sensitivities; see docs/events.md) ---------

  /// True if rhs_at_event, event_indicator_tangent and handle_event_tangent
  /// are implemented (generated models with events).
  [[nodiscard]] virtual bool provides_event_tangents() const { return false; }
  /// xdot = f at an event instant, every relation on indicator i valued as
  /// after a crossing in direction relations_from[i] (0: evaluated as is).
  /// Pass the negated crossings for f just before the event.
  virtual void rhs_at_event(double t, std::span<const double> x, std::span<const double> u,
                            std::span<const double> p, std::span<const int> relations_from,
                            std::span<double> xdot);
  /// dg = g_x δx + g_d δd + g_u δu + g_p δp + g_t δt for every indicator,
  /// along `direction` (not changed), relations valued as in rhs_at_event.
  /// Throws std::logic_error (an internal error) unless provides_event_tangents().
  virtual void event_indicator_tangent(double t, std::span<const double> x,
                                       std::span<const double> u, std::span<const double> p,
                                       std::span<const int> relations_from,
                                       const EventTangent& direction, std::span<double> dg);
  /// handle_event(), and carries each direction through it: a reinitialised
  /// state's δx becomes r_x δx + r_d δd + r_u δu + r_p δp + r_t δt, and an assigned
  /// discrete variable with discrete sensitivities its δd likewise. If a
  /// fired when-clause assigns another discrete variable a value with a
  /// nonzero derivative, `unsupported` names it (its sensitivity is not
  /// carried). Throws std::logic_error unless provides_event_tangents().
  virtual EventResponse handle_event_tangent(const EventCause& cause, std::span<double> x,
                                             std::span<const double> u,
                                             std::span<const double> p,
                                             std::span<EventTangent> directions,
                                             std::string& unsupported);
  /// dτ along `direction` of a time event at t that sample() ticks cause:
  /// δstart + k·δinterval of the tick k (start and interval over the
  /// parameters); 0 without a tick at t or event tangents; NaN if two
  /// samples ticking at t move apart.
  virtual double time_event_tangent(double t, std::span<const double> x, std::span<const double> u,
                                    std::span<const double> p, const EventTangent& direction) {
    (void)t, (void)x, (void)u, (void)p, (void)direction;
    return 0.0;
  }
  /// After initial_state(): carries each direction (δx = ∂x0/∂p) through the
  /// when-clauses that fired in the event at initialisation, updating `d` as
  /// handle_event_tangent does (`unsupported` likewise). Does nothing for a
  /// model without event tangents.
  virtual void initial_event_tangent(double t0, std::span<const double> x,
                                     std::span<const double> u, std::span<const double> p,
                                     std::span<EventTangent> directions, std::string& unsupported) {
    (void)t0, (void)x, (void)u, (void)p, (void)directions, (void)unsupported;
  }

  // --- delay() (ModelInfo::num_delays > 0) ------------------------------------

  /// Records the delayed expressions' values at (t, x, u, p), the current
  /// discrete variables: the simulator calls it after every accepted step,
  /// and at an event before and after the handler. initial_state() records
  /// the start itself. `relations_from`, before the handler of a state
  /// event: the negated crossings (as rhs_at_event), so that a relation on a
  /// crossed indicator has its value from before the crossing. True if a
  /// delayed expression of the model (not one the sensitivity equations
  /// added) jumped: its value differs from the one recorded just before at
  /// the same time.
  virtual bool record_delays(double t, std::span<const double> x, std::span<const double> u,
                             std::span<const double> p, std::span<const int> relations_from = {}) {
    (void)t, (void)x, (void)u, (void)p, (void)relations_from;
    return false;
  }
  /// The shortest delay time at the parameters of the last initial_state()
  /// (the simulator's longest step); NaN if one is not in (0, delayMax].
  [[nodiscard]] virtual double shortest_delay() const { return std::numeric_limits<double>::infinity(); }

  /// Current discrete variables d (for results and for save/restore).
  [[nodiscard]] virtual std::span<double> discrete() { return {}; }
  /// Per when-clause (in the lowered model's order, every-event clauses
  /// included): how often it fired in handle_event() calls since the last
  /// call of this function or initial_state() (whose event at
  /// initialisation, and tick at t0, count). Sets the counts back to 0.
  /// Empty if the model does not count (hand-written models).
  virtual std::vector<int> take_fired_counts() { return {}; }

  /// Why the last evaluation gave non-finite values, if the model knows (e.g.
  /// a singular linear block, a nonlinear block that did not converge); empty
  /// otherwise. Cleared by the next evaluation that succeeds.
  [[nodiscard]] virtual std::string last_failure() const { return {}; }

  /// What the model's equation solvers did since the last initial_state()
  /// that its user should know, one line each (a linear block found singular
  /// and solved by its minimum-norm solution); empty if nothing.
  [[nodiscard]] virtual std::vector<std::string> notes() const { return {}; }
};

}  // namespace mo::runtime
