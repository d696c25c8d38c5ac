// The Optimica part of a study turned into model outputs: the objective, the
// integrand and every constraint expression become output variables of the
// flat model (with one equation each), so that code generation gives their
// values and exact derivatives like any other output. Point constraints
// (`x(finalTime) = 0.5`, `x(2.5) >= 0`) keep their time.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

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
};

/// What add_problem_outputs added.
struct ProblemOutputs {
  double t0 = 0.0, tf = 1.0;           ///< startTime, finalTime
  std::optional<std::string> mayer;    ///< output for `objective` (evaluated at tf)
  std::optional<std::string> lagrange; ///< output for `objectiveIntegrand`
  std::vector<ProblemConstraint> constraints;
};

/// Adds the outputs to `flat` (which must have an optimization part). Returns
/// nullopt after reporting what it cannot express (an objective at a time
/// other than finalTime, a constraint mixing times, non-constant times).
std::optional<ProblemOutputs> add_problem_outputs(frontend::flat::Model& flat,
                                                  frontend::DiagnosticEngine& diags);

/// The value of a flat expression built from literals, parameters with known
/// values and + - * / ^; nullopt otherwise.
std::optional<double> constant_value(const frontend::flat::Model& flat,
                                     const frontend::ast::Expr& e);

}  // namespace mo::tools
