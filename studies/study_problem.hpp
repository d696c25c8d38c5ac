// The Optimica part of a study turned into model outputs: the objective, the
// integrand and every constraint expression become output variables of the
// flat model (with one equation each), so that code generation gives their
// values and exact derivatives like any other output. Point constraints
// (`x(finalTime) = 0.5`, `x(2.5) >= 0`) keep their time.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "flat_constant.hpp"
#include "mo/frontend/diagnostics.hpp"
#include "mo/frontend/flat.hpp"

namespace mo::tools {

/// A constraint lo ≤ output ≤ hi, on the whole horizon or at one time.
struct ProblemConstraint {
  std::string output;         ///< name of the added output
  std::string variable;       ///< the constrained variable if the expression is just its name
  std::optional<double> time; ///< point constraint time; nullopt: path constraint
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  frontend::SourceRange range;
  /// For the constraint add_bound_constraints made from a variable's min/max:
  /// that variable (empty for a written constraint).
  std::string bounded_variable;
};

/// Optimica's free final time (`finalTime(free = true, ...)`): the study runs
/// on τ ∈ [0, 1] with t = start + (finalTime − start)·τ (study_time_scaling.hpp).
struct FreeFinalTime {
  std::int32_t var = -1;  ///< the flat parameter `finalTime`
  std::string parameter;  ///< its name
  double start = 0.0;     ///< startTime (fixed)
};

/// What add_problem_outputs added.
struct ProblemOutputs {
  double t0 = 0.0, tf = 1.0;           ///< startTime, finalTime (0 and 1 with a free final time)
  std::optional<FreeFinalTime> free_final_time;  ///< set iff finalTime is free
  std::optional<std::string> mayer;    ///< output for `objective` (evaluated at tf)
  std::optional<std::string> lagrange; ///< output for `objectiveIntegrand`
  std::vector<ProblemConstraint> constraints;
};

/// Adds the outputs to `flat` (which must have an optimization part). Returns
/// nullopt after reporting what it cannot express (an objective at a time
/// other than finalTime, a constraint mixing times, non-constant times).
std::optional<ProblemOutputs> add_problem_outputs(frontend::flat::Model& flat,
                                                  frontend::DiagnosticEngine& diags);

/// Optimica bounds on algebraic variables and outputs: for every continuous
/// Real unknown of `flat` (not a top-level input) with a constant `min` or
/// `max`, an output `$bounds[k]` = v and a path constraint min ≤ v ≤ max.
/// Call after add_problem_outputs; states keep their bounds as NLP variable
/// bounds (drop_state_bounds removes their duplicate rows after lowering).
void add_bound_constraints(frontend::flat::Model& flat, ProblemOutputs& out);

/// Removes the constraints add_bound_constraints made for variables that
/// lowering kept as states named in `states`.
void drop_state_bounds(ProblemOutputs& out, const std::vector<std::string>& states);

}  // namespace mo::tools
