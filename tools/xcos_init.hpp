// The init file that Scilab's Modelica translator writes beside a diagram's
// flat model (`<title>_imf_init.xml`, modelicat -with-init): one <terminal>
// per variable with its kind, `fixed` flag and initial (start) value. The
// flat .mo already holds every value the diagram sets; what only the init
// file holds are the fixed flags: a block variable declared `fixed = true`
// (a Coselica mass's position, a Modelica generic block's "fixed state") loses
// the flag in the flat .mo.
//
// Applied with --init-fixed as Scilab's initialisation dialog (and Modelica 3
// §8.6) reads it: a variable
// whose flag is "true" gets fixed = true (an initial equation v = start),
// unless the model declares it not fixed: the translator marks "true" every
// `fixed` that depends on a block parameter, whatever its value
// (xcos_fixed_flags.hpp).
// Parameters are left alone: Scilab writes fixed = false on every block
// parameter for its initialisation dialog, and with no initial equation to
// determine them they keep their values. Note that Scilab's own simulation
// (modelicac without the initialisation dialog) does not read the file and
// takes every start value as a guess or a state's initial value.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "mo/frontend/flat.hpp"

namespace mo::tools {

/// One <terminal> of the init file.
struct InitTerminal {
  std::string id;             ///< the flat variable's name, e.g. "Capacitor1.v"
  std::string kind;           ///< "variable", "fixed_parameter", "input", ...
  std::string fixed;          ///< "true", "false" or "" (unset)
  std::string initial_value;  ///< as written ("0.", "`v_42`", "")
};

/// Reads an init file (untrusted text: a real XML parser, expat, without
/// DTDs or entities; at most 256 MB). Throws std::runtime_error with
/// "FILE:LINE: error: ..." on malformed XML.
std::vector<InitTerminal> read_init_file(const std::filesystem::path& file);

/// What apply_init_file did.
struct InitFlags {
  std::vector<std::string> fixed;         ///< made fixed = true, in file order
  std::vector<std::string> not_declared;  ///< flagged, but `declared` says not fixed: left alone
};

/// Applies the fixed flags of `terminals` to `model` (see the file comment),
/// except those that `declared` (the model's own flags by the translator's
/// names, xcos_fixed_flags.hpp; may be null) says are false.
InitFlags apply_init_file(frontend::flat::Model& model, const std::vector<InitTerminal>& terminals,
                          const std::map<std::string, bool>* declared);

/// read_init_file + apply_init_file for `file` (nothing when empty), checked
/// against the declared flags of the hierarchical model beside it
/// (xcos_fixed_flags.hpp); lines for stderr naming what was applied and what
/// was left free, or why the flags went unchecked (empty when nothing). Throws
/// DiagramError (xcos_diagram.hpp) when the file is not well-formed XML.
std::string apply_diagram_init(frontend::flat::Model& model, const std::filesystem::path& file,
                               const std::string& tool);

}  // namespace mo::tools
