// The fixed flags a diagram's model declares, as a check on the init file.
//
// Scilab's translator writes fixed="true" into the init file for every
// variable whose `fixed` attribute is an expression of a block parameter,
// whatever the expression's value: Xcos declares every block parameter
// `fixed = false` (tunable), and the translator does not evaluate such
// expressions (measured with modelicat: `fixed = if k > 0 then true else
// false` and `fixed = if k > 0 then false else true` both give "true"). A
// Coselica joint declares `a(fixed = if initType[3] > 0 then true else
// false)` with initType = {0, 0, 0} by default, so every such variable of a
// Coselica diagram arrives marked fixed.
//
// The declared flags come from mocompile's own flattening of the
// hierarchical model the translator read (`<title>_im.mo`, beside the init
// file) with the files and folders it read (`translator_libs.txt`, which
// mocompile's Scilab script writes there), each `fixed` evaluated with the
// parameters' values.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "mo/frontend/flat.hpp"

namespace mo::tools {

/// A flat name in the translator's spelling: `a.b[1,2]` → `a.b.[1].[2]`.
std::string translator_name(const std::string& flat_name);

/// The declared fixed flag of every variable of `model` whose `fixed` is
/// absent, a literal, or an expression of parameters with known values,
/// under its name in the translator's spelling (absent: false).
std::map<std::string, bool> declared_fixed_flags(const frontend::flat::Model& model);

/// declared_fixed_flags of the hierarchical model beside `init_file`
/// (`<title>_imf_init.xml` → `<title>_im.mo`, `translator_libs.txt`).
/// nullopt, with the reason in `why`, when a file is missing or the model
/// does not flatten here.
std::optional<std::map<std::string, bool>> declared_fixed_flags(const std::filesystem::path& init_file,
                                                                std::string& why);

}  // namespace mo::tools
