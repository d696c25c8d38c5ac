// The order in which an event iteration evaluates the discrete equations
// outside when-clauses (every-event clauses) against the continuous steps.
#pragma once

#include <vector>

#include "mo/symbolic/ode.hpp"

namespace mo::symbolic {

/// For each when-clause of `model` (same order as model.whens): true for an
/// every-event clause whose values read no step target that depends, through
/// the steps, on a variable some every-event clause assigns; false for the
/// others and for ordinary when-clauses. Such a clause is computed from the
/// discrete values alone (and from states, parameters, time and steps the
/// discrete values do not move), so within one event iteration it is
/// evaluated before the continuous steps that read it: the MSL friction's
/// `locked = not (startForward or pre(mode) == Forward ...)` then decides
/// `sa` (through `a_relfric = if locked then 0 else ...`), rather than a
/// `startForward` computed from an `sa` that a stale `locked` gave.
std::vector<bool> every_event_before_steps(const OdeModel& model);

}  // namespace mo::symbolic
