// stateSelect = prefer / always on variables the model never differentiates.
//
// The MSL writes `v_rel = der(s_rel)` with stateSelect = prefer on both s_rel
// and v_rel, and never der(v_rel): structurally v_rel is only the derivative
// of s_rel, so Pantelides' algorithm cannot offer it as a state, and the
// absolute velocity of a neighbouring mass is chosen instead. Other Modelica
// tools make such a variable a state where the model allows it (the spec:
// prefer "use it as a state over those with the default value", always "do
// use it as a state"). Which variables are states is not a detail: a
// `reinit` of one state keeps the others, so the choice shows in results
// (the MSL's MassWithStopAndFriction hitting its stop next to a SpringDamper).
#pragma once

#include <optional>
#include <vector>

#include "dae.hpp"
#include "mo/frontend/diagnostics.hpp"

namespace mo::symbolic::detail {

/// Pantelides' algorithm and state selection (index_reduction.hpp), after
/// giving every live variable with stateSelect prefer or always that has no
/// derivative yet a derivative variable, so that it is a state candidate.
/// That trial is kept only for the variables it makes states; when it cannot
/// be carried out (an equation that would need differentiating involves an
/// input, or the system is singular with the added derivatives) the DAE is
/// reduced as the model wrote it. Returns the states (as select_states), or
/// nullopt after reporting to `diags`.
std::optional<std::vector<bool>> reduce_index(Dae& dae, frontend::DiagnosticEngine& diags);

}  // namespace mo::symbolic::detail
