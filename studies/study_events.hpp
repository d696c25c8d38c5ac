// Studies on models with events: which models switch, and where (for diagnostics).
#pragma once

#include <optional>

#include "mo/frontend/diagnostics.hpp"
#include "mo/frontend/flat.hpp"
#include "mo/symbolic/ode.hpp"

namespace mo::tools {

/// True if `ode` has when-clauses, event indicators or sample() time events.
inline bool has_events(const symbolic::OdeModel& ode) {
  return !ode.whens.empty() || !ode.zero_crossings.empty() || !ode.samples.empty();
}

/// Where the model switches, for a diagnostic: the `when`-th when/elsewhen
/// branch of `flat` (in the order lowering numbers OdeModel::whens) if given
/// and found, else the first when-clause or relation, else the optimization class.
frontend::SourceRange event_source(const frontend::flat::Model& flat, std::optional<std::size_t> when);

}  // namespace mo::tools
