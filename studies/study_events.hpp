// Studies on models with events: collocation assumes a smooth model.
#pragma once

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

}  // namespace mo::tools
