// The lowered model: the IR between lowering and code generation.
//
//   der(x) = f(x, u, p, t, d)     computed by `steps` in order,
//   y      = h(x, u, p, t, d)     outputs: expressions over anything the steps computed,
//   x(t0)  = x0(p)                start expressions over parameters (and the
//                                 symbols `initial_steps` solve for, when the
//                                 model has initial equations: the initial
//                                 system's blocks, run before the starts),
//
// Every unknown other than the states is an Algebraic symbol assigned by one
// step; each state's derivative is a Derivative symbol assigned by one step.
// A step is an explicit assignment or an equation block solved at run time:
// a linear block (A z = -c, A and c evaluated from the expressions below) or a
// nonlinear block (Newton on the residuals with the given Jacobian). Blocks
// are never inverted symbolically.
//
// Discrete variables d change only at events: when-clauses assign them and
// reinit states. Zero crossings are the event indicators of relations in the
// continuous equations and when-conditions.
#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "mo/symbolic/expr_arena.hpp"

namespace mo::symbolic {

/// What the modeller declared about a scalar that survives lowering.
/// The Modelica type a variable was declared with (enumerations are
/// Integer); every value is a double to the solvers, Booleans 0 or 1.
enum class ValueType : std::uint8_t { Real, Integer, Boolean };

struct VariableInfo {
  std::string name;         ///< flat Modelica name, e.g. "pendulum.phi" or "d(phi)/d(m2)"
  std::string description;  ///< the declaration's comment, may be empty
  std::string unit;         ///< unit attribute, may be empty
  double nominal = 1.0;     ///< scaling magnitude, > 0
  double min = -std::numeric_limits<double>::infinity();  ///< lower bound
  double max = std::numeric_limits<double>::infinity();   ///< upper bound
  ValueType type = ValueType::Real;                       ///< as declared, for the text form
};

/// A forward sensitivity state S = ∂x_state/∂p_parameter (indices into the model).
struct SensitivityOf {
  std::size_t state;      ///< index of the base state in OdeModel::states
  std::size_t parameter;  ///< index of the parameter in OdeModel::parameters
};

/// A state x_i with its derivative symbol and start expression.
struct OdeState {
  VariableInfo info;
  Expr symbol;      ///< role State
  Expr derivative;  ///< role Derivative; assigned by exactly one step
  Expr start;       ///< x0 as an expression over parameters (often a constant)
  bool fixed = false;  ///< start was declared fixed = true (else a guess)
  std::optional<SensitivityOf> sensitivity;  ///< set iff this is a sensitivity state
};

/// An input u_j, given over time by the caller.
struct OdeInput {
  VariableInfo info;
  Expr symbol;  ///< role Input
};

/// A parameter p_k with its default value.
struct OdeParameter {
  VariableInfo info;
  Expr symbol;         ///< role Parameter
  double value = 0.0;  ///< default value
};

/// An algebraic unknown, assigned by exactly one step.
struct OdeAlgebraic {
  VariableInfo info;
  Expr symbol;  ///< role Algebraic
};

/// A discrete sensitivity ∂d/∂p of a discrete variable whose when-clause
/// value depends on states, parameters or time (a sample-and-hold): constant
/// between events, set by the run time at each event (indices into the model).
struct DiscreteSensitivityOf {
  std::size_t discrete;   ///< index of the base discrete variable in OdeModel::discrete
  std::size_t parameter;  ///< index of the parameter in OdeModel::parameters
};

/// A discrete variable (Real, Integer or Boolean as double).
struct OdeDiscrete {
  VariableInfo info;
  Expr symbol;         ///< role Discrete; pre(symbol) is its value before an event
  double start = 0.0;  ///< value at t0
  std::optional<DiscreteSensitivityOf> sensitivity = {};  ///< set iff this is ∂d/∂p
};

/// A named value for results: a model output, or an eliminated variable.
struct OdeOutput {
  VariableInfo info;
  Expr value;  ///< expression over states, inputs, parameters, time, steps' targets
};

/// target := value. `target` is an Algebraic or Derivative symbol.
struct Assignment {
  Expr target;
  Expr value;
  std::string origin = {};  ///< the source equation, "file.mo:12:3: text", for messages; may be empty
};

/// One entry J(row, col) of a block's Jacobian ∂residual_row/∂unknown_col.
struct BlockEntry {
  std::size_t row;
  std::size_t col;
  Expr value;
};

/// Equations 0 = residuals[i] solved together for `unknowns`.
/// Linear: the residuals are affine in the unknowns, r = J z + offset, so the
/// run time solves J z = -offset (J and offset do not depend on z).
/// Nonlinear: Newton on r with Jacobian J, starting from the unknowns' last
/// values (their `start` at the first call).
struct EquationBlock {
  bool linear = true;
  std::vector<Expr> unknowns;       ///< Algebraic or Derivative symbols
  std::vector<Expr> residuals;      ///< one per unknown
  std::vector<BlockEntry> jacobian; ///< structurally nonzero entries, row-major
  std::vector<Expr> offset;         ///< linear only: r at z = 0
  std::vector<double> start;        ///< nonlinear only: first Newton guess
  std::vector<std::string> origins = {};  ///< per residual: its source equation (see Assignment::origin), or empty
};

/// One step of the evaluation sequence.
using Step = std::variant<Assignment, EquationBlock>;

/// reinit(state, value) inside a when-clause.
struct Reinit {
  std::size_t state;  ///< index into OdeModel::states
  Expr value;
};

/// when condition then discrete := value ...; reinit(...) ...; end when.
/// Fires when `condition` becomes true (it was false before the event).
struct WhenClause {
  Expr condition;                       ///< Boolean expression (0/1)
  /// Fires at every handler call instead (each event iteration): the
  /// equation `d = expr` of a discrete variable that reads pre(), outside
  /// when-clauses (the MSL's friction `mode`, `startForward`, `locked`). The
  /// relations of its values are event indicators.
  bool every_event = false;
  std::vector<Assignment> assignments;  ///< targets are Discrete symbols
  std::vector<Reinit> reinits;
  bool terminates = false;         ///< terminate(): the simulation ends successfully when it fires
  std::string terminate_message;   ///< terminate()'s text
  /// `when c0 then ... elsewhen c1 then ...`: the clauses of one when-equation
  /// share `group` (>= 0; -1 for a clause alone), `branch` is the index of the
  /// branch they come from (a vector condition gives a clause per element, of
  /// the same branch). A clause does not fire at an instant where a clause of
  /// an earlier branch of its group is activated (Modelica 3 §8.3.5), unless
  /// the group is not `prioritised`.
  std::int32_t group = -1;
  std::int32_t branch = 0;
  /// False for a when-equation whose branches assign different variables:
  /// Modelica forbids it (§8.3.5.2); Scilab's modelicac, for which Coselica's
  /// friction elements are written so, fires every branch whose condition
  /// becomes true, and so do its clauses here.
  bool prioritised = true;
};

/// `sample(start, interval)`: time events at exactly start + k·interval,
/// k = 0, 1, ... (each time computed from k, so no rounding accumulates).
/// The call reads a discrete flag that is 1 only during the handler calls of
/// such an event (0 between events and during initialisation; a tick at
/// t = 0 is an event right after the event at initialisation).
struct OdeSample {
  std::int32_t flag = -1;  ///< index into OdeModel::discrete of the flag, printed as the call
  Expr start;              ///< over parameters
  Expr interval;           ///< over parameters, > 0 at their values
};

/// The lowered model. Owns its expressions.
struct OdeModel {
  ExprArena arena;
  std::string name;
  Expr time;  ///< the Time symbol
  std::vector<OdeState> states;
  std::vector<OdeInput> inputs;
  std::vector<OdeParameter> parameters;
  std::vector<OdeAlgebraic> algebraics;
  std::vector<OdeDiscrete> discrete;
  std::vector<Step> steps;          ///< evaluation order
  std::vector<OdeOutput> outputs;   ///< declared outputs (and output sensitivities)
  std::vector<OdeOutput> eliminated;  ///< aliases and other removed variables, for results
  /// Blocks of the initial system (and what follows from them), evaluated at
  /// t0 with the inputs' values u(t0) before the start expressions, which may
  /// use their unknowns; empty when every start value is an expression over
  /// parameters (and inputs, time).
  std::vector<Step> initial_steps;
  std::vector<OdeAlgebraic> initial_unknowns;  ///< the symbols initial_steps assign
  std::vector<Expr> zero_crossings; ///< event indicators: sign changes are events
  /// Per zero crossing: true if a relation on it appears in `steps` (the
  /// right-hand side). One that only when-conditions and discrete equations
  /// read changes nothing continuous when it crosses, and an event at it
  /// that changes no discrete value needs no restart of the integrator.
  std::vector<bool> zero_crossing_in_steps;
  std::vector<WhenClause> whens;
  /// Index into `discrete` of the flag `initial()` reads, or -1 when the
  /// model does not call initial(). The flag is 0 except during the event at
  /// initialisation (the run time's initial_state), where it is 1: when-clauses
  /// on initial() (and the `initial algorithm` assignments of discrete
  /// variables, lowered to such clauses) fire there.
  std::int32_t initial_flag = -1;
  std::vector<OdeSample> samples;  ///< the distinct sample() calls (time events)

  /// Index of the parameter named `name`, or nullopt.
  [[nodiscard]] std::optional<std::size_t> parameter_index(std::string_view name) const;
  /// Index of the state named `name`, or nullopt.
  [[nodiscard]] std::optional<std::size_t> state_index(std::string_view name) const;
  /// Number of states that are not sensitivity states.
  [[nodiscard]] std::size_t num_base_states() const;
  /// Per input: true if the start expressions or initial_steps read it (the
  /// start values then depend on u(t0)).
  [[nodiscard]] std::vector<bool> inputs_in_initial_system() const;
  /// Every expression the steps compute (assigned values, block residuals,
  /// offsets and Jacobian entries), then the outputs' values.
  [[nodiscard]] std::vector<Expr> equation_expressions() const;
  /// The event expressions: zero crossings, then per when-clause its
  /// condition, assigned values and reinit values.
  [[nodiscard]] std::vector<Expr> event_expressions() const;
};

/// The model as flat Modelica that parses and simulates again: declarations
/// (states with start/fixed, algebraics, parameters, inputs, outputs), then
/// the steps in order (`der(x) = ...`, `a = ...`, blocks as `0 = ...`), the
/// outputs and the when-clauses. Names are quoted where Modelica needs it.
std::string print_ode(const OdeModel& model);

/// A short text summary: sizes and the kinds of steps (for logs and tests).
std::string summary(const OdeModel& model);

}  // namespace mo::symbolic
