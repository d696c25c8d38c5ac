// The implicit DAE 0 = F(der(x), x, y, u, p, t) that lowering works on: the
// flat model's unknowns as symbols, each derivative a variable of its own
// (der(x) is the variable `A(x)` of Pantelides' algorithm, der(der(x)) its
// derivative, ...), equations as residual expressions.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "mo/frontend/source.hpp"
#include "mo/symbolic/ode.hpp"

namespace mo::symbolic::detail {

inline constexpr int none = -1;

/// A continuous unknown, or a derivative of one.
struct DaeVar {
  VariableInfo info;
  Expr symbol;               ///< role Algebraic until states are chosen
  int derivative = none;     ///< the variable that is der(this), once it exists
  int integral = none;       ///< the variable this is der() of, or none
  Expr start;                ///< start expression (constant or over parameters), may be invalid
  bool fixed = false;        ///< start declared fixed = true
  bool start_given = false;  ///< a start attribute was declared
  /// The start was written by a user of the declaring class, or the variable
  /// is the model's own (flat::Variable::start_by_user): the author's guess,
  /// which tearing prefers as an iteration variable.
  bool start_guess = false;
  bool source_derivative = false;  ///< der() of it is in the model (after aliases), not made by index reduction
  bool linear_derivative = false;  ///< ... in some equation with a time-invariant coefficient
  std::string state_select;  ///< "", never, avoid, default, prefer, always
  bool eliminated = false;   ///< removed by alias elimination
  frontend::SourceRange range;
};

/// 0 = residual.
struct DaeEq {
  Expr residual;
  frontend::SourceRange range;
  int derivative = none;  ///< the equation that is d/dt of this one, once made
  int integral = none;    ///< the equation this one is d/dt of
  int lhs_var = none;     ///< variable alone on the left of `v = expr` as written (after aliases)
  bool removed = false;   ///< consumed by alias elimination
};

/// when-clause with its (continuous-time) condition.
struct DaeWhen {
  Expr condition;
  /// An equation `d = expr` of a discrete variable outside when-clauses that
  /// reads pre(): evaluated at every event iteration (condition unused).
  bool every_event = false;
  std::vector<Assignment> assignments;  ///< targets are Discrete symbols
  std::vector<std::pair<int, Expr>> reinits;  ///< (DaeVar index, value)
  bool terminates = false;                    ///< terminate(message) in the clause
  std::string terminate_message;              ///< its text (a literal or a String parameter's value)
  std::int32_t group = -1;                    ///< WhenClause::group
  std::int32_t branch = 0;                    ///< WhenClause::branch
  bool prioritised = true;                    ///< WhenClause::prioritised
  frontend::SourceRange range;
};

/// der(v) in an initial equation of a variable v that the model's equations
/// do not differentiate: a placeholder symbol (no DaeVar), which the initial
/// system defines as the time derivative of v's value there
/// (initial_system.hpp).
struct InitialDerivative {
  int var = none;
  Expr symbol;
};

struct Dae {
  ExprArena arena;
  std::string name;
  Expr time;
  std::vector<DaeVar> vars;
  std::vector<DaeEq> eqs;
  /// The `initial equation` sections: 0 = residual at t0 only (over the same
  /// symbols; alias elimination substitutes into them too).
  std::vector<DaeEq> initial_eqs;
  std::vector<InitialDerivative> initial_derivatives;  ///< placeholders in initial_eqs
  std::vector<OdeInput> inputs;
  std::vector<OdeParameter> parameters;
  std::vector<OdeDiscrete> discrete;
  std::vector<OdeOutput> outputs;     ///< top-level outputs: name → their variable
  std::vector<OdeOutput> eliminated;  ///< alias-eliminated variables
  std::vector<DaeWhen> whens;
  /// Index into `discrete` of the flag `initial()` reads, or -1 (not used).
  std::int32_t initial_flag = -1;
  std::vector<OdeSample> samples;  ///< the distinct sample() calls and their flags
  /// Symbol id → DaeVar index (for Algebraic symbols made by lowering).
  std::vector<int> var_of_symbol;
  /// Prefix of the internal names add_var gives symbols. A trial that is
  /// rolled back leaves its symbols in the arena; changing the prefix keeps
  /// the variables made after it from colliding with them.
  std::string symbol_prefix = "\x1f";

  /// The variable a Symbol stands for, or none (parameters, inputs, time...).
  [[nodiscard]] int var_of(Expr symbol) const {
    const auto info_index = symbol.id();
    return info_index < var_of_symbol.size() ? var_of_symbol[info_index] : none;
  }
  /// Adds a continuous variable with a fresh Algebraic symbol named `info.name`.
  int add_var(DaeVar v);
  /// The variable der(v), created (named "der(<name>)") on first use.
  int derivative_of(int v);
};

}  // namespace mo::symbolic::detail
