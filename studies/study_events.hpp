// Studies on models with events: collocation assumes a smooth model.
#pragma once

#include <optional>

#include "mo/frontend/diagnostics.hpp"
#include "mo/frontend/flat.hpp"
#include "mo/symbolic/ode.hpp"

namespace mo::tools {

/// True if `ode` switches (when-clauses, or relations that are event
/// indicators); then reports an error at the first when-clause or relation of
/// `flat` naming it: optimal_control, design, estimation and monte_carlo
/// solve by a collocation that would ignore the switch.
bool reject_events_in_study(const frontend::flat::Model& flat, const symbolic::OdeModel& ode,
                            frontend::DiagnosticEngine& diags);

/// True if `ode` has when-clauses or event indicators.
inline bool has_events(const symbolic::OdeModel& ode) { return !ode.whens.empty() || !ode.zero_crossings.empty(); }

/// Where the model switches, for a diagnostic: the `when`-th when/elsewhen
/// branch of `flat` (in the order lowering numbers OdeModel::whens) if given
/// and found, else the first when-clause or relation, else the optimization class.
frontend::SourceRange event_source(const frontend::flat::Model& flat, std::optional<std::size_t> when);

}  // namespace mo::tools
