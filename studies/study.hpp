// `morun study.opt`: an Optimica optimization class run end to end.
//
//   flat model ─ objective/constraints as outputs ─ lower (+ sensitivities for
//   design) ─ generate, compile (cached) ─ optimal control | input design |
//   estimation ─ DIR/summary.json, trajectories.csv, resimulated.csv,
//   ipopt.log, designed_input.csv / fit.csv, PNG plots
#pragma once

#include <string>
#include <vector>

#include "mo/frontend/diagnostics.hpp"
#include "mo/frontend/flat.hpp"
#include "progress.hpp"

namespace mo::tools {

/// What the command line says about a study.
struct StudyCli {
  std::string output = "results";           ///< result directory
  std::string study_file;                   ///< for relative data paths in the annotation
  std::vector<std::string> overrides_text;  ///< --option name=value
  std::vector<std::string> sets;            ///< --set p=v: parameter values of the study
  unsigned jobs = 2;                        ///< parallel compile jobs
  bool plot = false;                        ///< --plot (the option `plot` also enables it)
  bool quiet = false;                       ///< --quiet: no progress, no compile note
  RunContext* run = nullptr;                ///< progress and timings of the run, may be null
};

/// Runs the study of `flat` (which must have an optimization part; it gains
/// the problem's outputs). Returns the exit status: 0 solved, 1 model or
/// solver failure (results written as far as they exist), 2 bad options.
/// Throws UsageError for command-line mistakes.
int run_study(frontend::flat::Model& flat, const StudyCli& cli, frontend::DiagnosticEngine& diags);

}  // namespace mo::tools
