// Multistart input design: the design solved from every start (multistart_
// starts.hpp) on the parallel runner (forked workers, MPI ranks), the local
// optima found, and the best design as the study's result.
//
// Local optima: the starts that converged (status success or acceptable) are
// sorted by their criterion value I (the information in collocation: trace F,
// log det F, λ_min F or −trace F⁻¹; ties by start number) and grouped
// greedily: a start joins the current optimum when |I − I_best| ≤
// cluster_tol · max(1, |I_best|, |I|), I_best being the optimum's best start,
// and opens a new one otherwise. The floor 1 keeps the test meaningful for
// D, whose log det may be near 0 (there it bounds the relative change of det F).
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "mo/runtime/design.hpp"
#include "multistart_starts.hpp"
#include "progress.hpp"

namespace mo::tools {

/// How one start ended.
struct StartOutcome {
  std::size_t index = 0;   ///< 0-based start number
  std::string origin;      ///< "initial_guess", "listed" or "random"
  std::string label;       ///< the signal as written, or "random r (seed K)"
  std::string status;      ///< the optimisation status, or "error"
  bool converged = false;  ///< status success or acceptable
  int iterations = 0;      ///< Ipopt iterations
  double objective = 0.0;  ///< objective at the returned point
  double information_collocation = 0.0;  ///< criterion of F in collocation (NaN if undefined)
  double information_resimulated = 0.0;  ///< criterion of the re-simulated F (NaN on failure)
  double seconds = 0.0;    ///< wall time of this start's solve
  std::string error;       ///< why the start produced no result (worker died, exception)
  std::string hessian;     ///< Hessian of the kept solve: "exact" or "limited_memory"
  std::size_t attempts = 0;  ///< solves: 2 when the limited-memory fallback ran
};

/// One local optimum: the starts that reached it (see the rule above).
struct LocalOptimum {
  double information_collocation = 0.0;  ///< of its best start
  double information_resimulated = 0.0;  ///< of its best start
  double objective = 0.0;                ///< of its best start
  std::vector<std::size_t> starts;       ///< 0-based, best first
};

/// Groups the converged starts into local optima, best optimum first.
std::vector<LocalOptimum> cluster_optima(const std::vector<StartOutcome>& starts, double tolerance);

/// How the starts are run.
struct MultistartSettings {
  unsigned jobs = 1;               ///< local worker processes (-j)
  std::string output_dir;          ///< per-start Ipopt logs go to DIR/starts/ipopt_<k>.log
  double cluster_tol = 1e-4;       ///< relative tolerance of cluster_optima
  RunContext* run = nullptr;       ///< progress line, may be null
};

/// Everything a multistart found.
struct MultistartResult {
  runtime::InputDesignResult best;  ///< the best converged start's result (start 1's if none converged)
  std::size_t best_start = 0;       ///< 0-based
  std::vector<StartOutcome> starts;  ///< by start number
  std::vector<LocalOptimum> optima;  ///< best first
};

/// Solves `d` from every start (start k's guesses replace the controls'
/// initial guesses; `d.starts` is ignored). Rank 0 (and a run without MPI)
/// gets the result; other MPI ranks get nullopt after their share.
std::optional<MultistartResult> run_multistart(const runtime::Model& model, const runtime::InputDesignProblem& d,
                                               const std::vector<DesignStart>& starts,
                                               const MultistartSettings& settings);

/// summary.json's design.multistart: starts, local optima, how many reached the best.
nlohmann::json multistart_json(const MultistartResult& m, const MultistartSettings& settings);

/// The local optima table and the count of starts that reached the best, on `os`.
void print_multistart(std::ostream& os, const MultistartResult& m, const std::string& criterion,
                      const MultistartSettings& settings);

}  // namespace mo::tools
