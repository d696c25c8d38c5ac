// Pieces of the optimal-control driver shared with input design and estimation.
#pragma once

#include "collocation_nlp.hpp"
#include "ipopt_solve.hpp"

namespace mo::runtime::detail {

/// The experiment part of an optimal control problem.
ExperimentSetup experiment_setup(const OptimalControlProblem& problem);
/// The shared part (parameters, discretisation) of an optimal control problem.
NlpSetup nlp_setup(const OptimalControlProblem& problem);
/// Adds the problem's Mayer/Lagrange terms and path/point constraints for experiment e.
/// Throws ProblemError on an output index out of range.
void add_problem_terms(CollocationNlp& nlp, const OptimalControlProblem& problem, int e);
/// Result of experiment e at the solver's last iterate, with the re-simulation check
/// (path constraints enter the bound violation).
OptimizationResult collect_result(CollocationNlp& nlp, const IpoptOutcome& outcome, int e,
                                  const std::vector<PathConstraint>& path);
/// A result that only carries a failure to build the problem.
OptimizationResult invalid_problem_result(const std::string& message);

}  // namespace mo::runtime::detail
