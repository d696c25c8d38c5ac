// The forward sensitivity system of a lowered model:
//
//   der(S_ik) = d der(x_i)/d p_k   through the steps by the chain rule,
//   S_ik(t0)  = ∂x0_i/∂p_k         (start values that depend on p_k count),
//   d(y)/d(p_k) outputs            = dy/dp_k along the same direction.
//
// Only structurally nonzero sensitivities exist: S_ik is a state only if x_i
// depends on p_k through its start value or its dynamics, or if p_k reaches
// an event expression (indicator, when-condition, reinit, discrete
// assignment): then every base state gets one, since the jump of S at the
// event (docs/events.md) may reach any state, and every discrete variable
// that a when-clause sets from states, parameters or time gets a discrete
// sensitivity d(d)/d(p_k) (OdeDiscrete::sensitivity), which the equations
// read and the run time sets at events.
#pragma once

#include <span>
#include <string>

#include "mo/symbolic/ode.hpp"

namespace mo::symbolic {

/// The name of ∂variable/∂parameter, e.g. "d(phi)/d(m2)".
std::string sensitivity_name(const std::string& variable, const std::string& parameter);

/// Appends the sensitivity states, steps and output sensitivities for the
/// parameters with the given indices to `model`. Sensitivity states come after
/// the base states, grouped by parameter. Throws std::invalid_argument for a
/// parameter index out of range or listed twice, or if the model already has
/// sensitivity states.
void add_sensitivities(OdeModel& model, std::span<const std::size_t> parameters);

}  // namespace mo::symbolic
