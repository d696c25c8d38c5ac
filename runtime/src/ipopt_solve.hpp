// Solving a CollocationNlp with Ipopt (TNLP interface), with retries when the
// linear algebra fails: MUMPS without scaling, then with more working memory,
// then with the other NLP scaling method.
#pragma once

#include "collocation_nlp.hpp"

#include <string>
#include <vector>

namespace mo::runtime::detail {

/// What Ipopt returned, mapped to the runtime's types.
struct IpoptOutcome {
  OptimizationStatus status = OptimizationStatus::solver_error;
  std::string message;
  std::vector<std::string> retries;
  double objective = 0.0;
  int iterations = 0;
  KktResiduals kkt;
  std::vector<double> solution;  ///< last iterate (the initial guess if none was reached)
  NlpSize size;
  double solve_seconds = 0.0;
  double evaluation_seconds = 0.0;
};

/// Runs Ipopt on `nlp` with `options`; never throws on solver failure.
IpoptOutcome solve_with_ipopt(CollocationNlp& nlp, const SolverOptions& options);

}  // namespace mo::runtime::detail
