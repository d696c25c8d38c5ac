// The Xcos corpus check (issue 10): every diagram of <shared>/xcos-corpus
// through the steps a user takes, compared with Scilab's own simulation.
//
//   flat    flat/NAME.mo (what modelicat wrote) parses and flattens
//   hier    flat/NAME_hier.mo flattens with Coselica.mo, Scilab's Electrical.mo
//           and Hydraulics.mo and flat/aux/NAME/*.mo, to the flat file's unknowns
//   lower   the flat model lowers, keeping no more states than modelicac did
//   simulate  the lowered model compiles and simulates to tf, inputs driven by
//           the recorded input columns of ref/NAME.csv
//   compare every state, algebraic and output column of ref/NAME.csv matches
//           over rows 2..N-1 to 1e-3 of the column's range (1e-2 where Scilab
//           ran with rtol > 1e-6)
//
// Used by the slow e2e test (tests/e2e/test_xcos_corpus.cpp) and by
// bench/xcos_corpus (the table).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace mo::xcos_corpus {

/// The corpus folder: $MO_SHARED_DIR/xcos-corpus, else
/// <source_dir>/../shared/xcos-corpus; nullopt when neither exists.
std::optional<std::string> corpus_dir(const std::string& source_dir);

/// The diagram names of the corpus (ref/*.json), sorted.
std::vector<std::string> diagrams(const std::string& corpus);

/// Where the libraries of the hierarchical files are.
struct Libraries {
  std::string coselica;        ///< Coselica.mo
  std::string scilab_macros;   ///< folder with Electrical.mo and Hydraulics.mo
};

/// The outcome of one step: passed, or why not.
struct StepResult {
  bool ran = false;     ///< false: an earlier step failed, not attempted
  bool passed = false;
  std::string detail;   ///< short reason or figure ("3 states", "max err 2e-4 of range")
};

/// The steps of one diagram, in order flat, hier, lower, simulate, compare.
struct DiagramResult {
  std::string name;
  StepResult flat, hier, lower, simulate, compare;
  [[nodiscard]] bool passed() const {
    return flat.passed && hier.passed && lower.passed && simulate.passed && compare.passed;
  }
};

/// Runs every step for diagram `name` of `corpus`. Compiled models go to the
/// compile cache ($XDG_CACHE_HOME). Never throws for a failing diagram.
DiagramResult check_diagram(const std::string& corpus, const std::string& name, const Libraries& libs);

/// Diagram `name` closed through Modelica copies of its non-Modelica blocks:
/// `loop_file` holds a model with one component, `component`, of the flat
/// file's class, and the blocks (in Modelica) that drive its inputs from its
/// outputs. The loop is simulated without inputs and its `component.X`
/// columns are compared with the reference's X as in check_diagram. Evidence
/// for a diagram whose recorded input samples cannot resolve its switching
/// (docs/xcos-dialect.md); never throws.
StepResult check_closed_loop(const std::string& corpus, const std::string& name, const std::string& loop_file,
                             const std::string& component);

/// One Markdown table row: | name | flat | hier | lower | simulate | compare |.
std::string table_row(const DiagramResult& r);

/// The Markdown table header (two lines).
std::string table_header();

}  // namespace mo::xcos_corpus
