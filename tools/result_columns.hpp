// Which variables result.csv holds: by default every variable of the flat
// model (states, algebraic variables, discrete variables, outputs and the
// variables lowering eliminated, under their flat names), optionally filtered
// by a regular expression (OpenModelica's variableFilter); and the rows that may be kept
// after a failure (never a row with NaN or infinity).
#pragma once

#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "mo/runtime/result.hpp"
#include "mo/symbolic/ode.hpp"

namespace mo::tools {

/// Appends to `ode.outputs` the first `algebraics` algebraic variables (those
/// of the model, not of its sensitivity equations) and every eliminated
/// variable and every discrete variable (as the event handler last left it)
/// whose name is not already a state or an output, each as an output of its
/// own value, so that the simulation reports it. Returns how many were added.
std::size_t add_all_variables(symbolic::OdeModel& ode, std::size_t algebraics);

/// The columns of `table` whose names match `filter` entirely (time is always
/// kept), in their order. `filter` empty: the table unchanged.
runtime::ResultTable select_columns(const runtime::ResultTable& table, const std::optional<std::regex>& filter);

/// The first row of `table` holding a value that is not finite, or nullopt.
std::optional<std::size_t> first_non_finite_row(const runtime::ResultTable& table);

/// The names of the columns not finite in row `k`, comma-separated (at most
/// `limit` names, then ", ...").
std::string non_finite_columns(const runtime::ResultTable& table, std::size_t k, std::size_t limit = 8);

/// The rows of `table` before row `end`.
runtime::ResultTable first_rows(const runtime::ResultTable& table, std::size_t end);

}  // namespace mo::tools
