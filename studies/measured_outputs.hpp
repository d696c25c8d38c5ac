// Measuring any variable: JModelica's experiment design and parameter
// estimation measure states and algebraic variables as well as declared
// outputs. The named variables become outputs of the lowered model, so that
// trajectories, measurement files, Fisher matrices and fits see them.
#pragma once

#include <string>
#include <vector>

#include "mo/symbolic/ode.hpp"

namespace mo::tools {

/// For every name in `names` that is not already an output of `model`: adds
/// an output of that name whose value is the state, algebraic variable,
/// input, parameter or eliminated variable of that name. Call before
/// sensitivities are added (they then include d(name)/d(p)). Returns the
/// names that are none of these, for the caller's diagnostic.
std::vector<std::string> add_measured_outputs(symbolic::OdeModel& model,
                                              const std::vector<std::string>& names);

/// The column names after `time` of a measurement CSV's header (the first
/// line that is neither empty nor a `#` comment); empty if unreadable or a
/// .mat file (whose measured vectors are named by study option outputs).
std::vector<std::string> csv_columns(const std::string& path);

}  // namespace mo::tools
