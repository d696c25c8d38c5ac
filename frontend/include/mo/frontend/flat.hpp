#pragma once
/// The flat model: scalar variables and scalar equations
///     0 = F(der(x), x, y, u, p, t)
/// plus when-clauses (v = expr, reinit(x, e)), initial equations and, for an
/// Optimica class, the optimization problem. Expressions are ast::Expr trees
/// whose references are resolved: Expr::var indexes `variables`. Parameters
/// stay parameters with their (flat) binding; constants are substituted.
/// print() writes flat Modelica that parses back to the same model.
#include "mo/frontend/ast.hpp"

#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace mo::frontend::flat {

enum class BaseType : std::uint8_t { Real, Integer, Boolean, String };
const char *base_type_text(BaseType t);

/// Attributes of a scalar variable; null expressions are unset.
struct Attributes {
  ast::ExprPtr start, fixed, min, max, nominal, free, initial_guess;
  std::string unit, display_unit, quantity;
  std::string state_select; ///< "", "never", "avoid", "default", "prefer", "always"
};

struct Variable {
  std::string name; ///< flat name, e.g. "R1.p.v" or "x[2]"
  BaseType type = BaseType::Real;
  ast::Variability variability = ast::Variability::Continuous;
  ast::Causality causality = ast::Causality::None;
  bool is_flow = false;
  bool is_stream = false; ///< a `stream` connector variable (no connection equations of its own)
  bool top_level_input = false; ///< an input of the model itself: known, not solved for
  /// The start attribute is the author's, not the declaring class's default:
  /// a user of that class (a modification from outside it) wrote the start,
  /// or made it an initial value (fixed = true), or the variable is the
  /// model's own.
  bool start_by_user = false;
  ast::ExprPtr binding;         ///< parameters only: the value expression
  std::optional<double> value;  ///< parameters: the binding evaluated, when it can be
  Attributes attr;
  std::string description;
  SourceRange range;            ///< the declaration in the source
  bool evaluate = false;        ///< parameters: `annotation(Evaluate = true)`, a structural value
  bool is_unknown() const {
    return (variability == ast::Variability::Continuous ||
            variability == ast::Variability::Discrete) && !top_level_input;
  }
  /// A parameter declared `fixed = false` (literally): the initial equations
  /// may compute it.
  bool free_parameter() const {
    const ast::Expr *fixed = attr.fixed.get();
    return variability == ast::Variability::Parameter && fixed &&
           fixed->kind == ast::ExprKind::Boolean && fixed->number == 0.0;
  }
};

/// One `name = value` of a class's `__mocompile` annotation.
struct StudyOption {
  std::string name;
  ast::ExprPtr value;  ///< null if written without a value
  SourceRange range;
};

/// Optimica: `objective`, `objectiveIntegrand`, `startTime`, `finalTime`
/// and the constraint section (EquationKind::Constraint equations).
struct Optimization {
  ast::ExprPtr objective, objective_integrand, start_time, final_time;
  /// `finalTime(free = true, ...)`: the parameter variable `finalTime` (free,
  /// with the min/max/initialGuess written) that `finalTime` refers to in the
  /// objective and constraints; -1 when the final time is fixed.
  std::int32_t free_final_time = -1;
  std::vector<ast::Equation> constraints;
  SourceRange range;
  /// `annotation(__mocompile(name = value, ...))` of the optimization class:
  /// study options, values as written (not resolved or evaluated).
  std::vector<StudyOption> options;
};

struct Model {
  std::string name;
  std::vector<Variable> variables;
  std::unordered_map<std::string, std::int32_t> index; ///< flat name → variable
  /// EquationKind Simple, If (non-parameter conditions), When, Call (assert...).
  std::vector<ast::Equation> equations;
  std::vector<ast::Equation> initial_equations;
  std::optional<Optimization> optimization;

  /// Adds a variable; returns its index (the name must be new).
  std::int32_t add(Variable v);
  /// Index of `name`, or -1.
  std::int32_t find(const std::string &name) const;
  /// The flat Modelica text of the model.
  std::string print() const;
};

/// Scalar equations a (flattened) equation contributes to the balance:
/// 1 for `a = b`, the assigned variables of a when-clause, the equations of
/// one branch of an if-equation; 0 for reinit, assert and the like.
std::size_t equation_count(const ast::Equation &eq);

} // namespace mo::frontend::flat
