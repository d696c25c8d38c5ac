// The front half of the pipeline shared by mocompile and morun:
//
//   .mo files ─ parse ─ flatten ─ lower ─ (sensitivities) ─ OdeModel
//
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mo/frontend/diagnostics.hpp"
#include "mo/frontend/flat.hpp"
#include "mo/frontend/flatten.hpp"
#include "mo/frontend/source.hpp"
#include "mo/symbolic/ode.hpp"

namespace mo::tools {

/// The .mo files of a library argument: the file itself, or every .mo file
/// under a directory (package.mo files first, so `within` packages exist).
std::vector<std::string> library_files(const std::string& arg);

/// Prepares `lib` for compiling `main_file`: loads each -L argument (a file;
/// a package directory with package.mo, whose classes are parsed when lookup
/// reaches them; or a directory whose .mo files are all parsed), then adds the
/// lookup roots for classes found nowhere else: the directory of `main_file`,
/// then each entry of the environment variable MODELICAPATH (':' or ';').
void load_libraries(frontend::Library& lib, const std::vector<std::string>& libs,
                    const std::string& main_file, frontend::SourceManager& sources,
                    frontend::DiagnosticEngine& diags);

/// What to load and flatten.
struct ModelSource {
  std::string file;                ///< the file holding the class
  std::string class_name;          ///< dotted path; empty: the file's last class
  std::vector<std::string> libs;   ///< library files or directories
  bool check_balance = true;
};

/// Parses the files (into `sources`, which `diags` refers to) and flattens
/// the class. On errors reports them to `diags` and returns nullptr.
std::unique_ptr<frontend::flat::Model> load_flat_model(const ModelSource& source,
                                                       frontend::SourceManager& sources,
                                                       frontend::DiagnosticEngine& diags);

/// flat → ODE. Returns nullopt after reporting to `diags`. With `trace`,
/// appends the text dump of each lowering stage to it.
std::optional<symbolic::OdeModel> lower_model(const frontend::flat::Model& flat,
                                              frontend::DiagnosticEngine& diags,
                                              std::string* trace = nullptr);

/// For every name "x.start" in `names` where x is a state and "x.start" is not
/// already a parameter: makes x's start value a new parameter of that name
/// (default: the start value at the default parameters), so that --set and
/// --sensitivities reach initial conditions. Names without ".start" are ignored.
void expose_start_parameters(symbolic::OdeModel& model, const std::vector<std::string>& names);

/// Appends forward sensitivities for the named parameters. Returns an error
/// message naming an unknown parameter, or empty on success.
std::string add_named_sensitivities(symbolic::OdeModel& model, const std::vector<std::string>& names);

}  // namespace mo::tools
