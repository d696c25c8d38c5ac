// Index reduction: Pantelides' algorithm finds the equations to differentiate
// (and differentiates them symbolically); dummy-derivative selection
// (Mattsson–Söderlind) then decides which differentiated variables stay states.
#pragma once

#include <vector>

#include "dae.hpp"
#include "mo/frontend/diagnostics.hpp"

namespace mo::symbolic::detail {

/// Unknowns (DaeVar indices) each live equation depends on; empty for removed
/// equations. Eliminated variables do not appear.
std::vector<std::vector<int>> incidence(const Dae& dae);

/// Reports equations left without an unknown (over-determined) and variables
/// left without an equation (under-determined), at most 10 of each.
void report_singular(const Dae& dae, const std::vector<int>& eqs, const std::vector<int>& vars,
                     frontend::DiagnosticEngine& diags);

/// True if the live equations can be matched to the variables when each
/// variable counts together with its derivatives; otherwise reports the
/// over- and under-determined parts (no differentiation can help) and
/// returns false.
bool structurally_regular(const Dae& dae, frontend::DiagnosticEngine& diags);

/// Checks structurally_regular, then runs Pantelides' algorithm on the live equations: adds differentiated
/// equations (DaeEq::integral links) and derivative variables until every
/// equation can be matched to a highest-derivative variable. Returns false
/// after reporting a structurally singular system (or an input that would
/// need differentiating) to `diags`.
bool pantelides(Dae& dae, frontend::DiagnosticEngine& diags);

/// Chooses the states: returns, per variable, true if it is a state (it has
/// a derivative variable and was not selected as a dummy). Honours
/// stateSelect (always: never a dummy; never/avoid: dummy first) and prefers
/// as dummies the variables a constraint was written to define (`v = ...`),
/// then those with the largest pivot |∂g/∂v| at the start values.
std::vector<bool> select_states(Dae& dae);

}  // namespace mo::symbolic::detail
