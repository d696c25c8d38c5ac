// Where a simulation's NaN or infinity comes from: re-evaluates the lowered
// model's steps at the failing point with the reference interpreter and
// names the first equation whose value is not finite although everything it
// uses is (a division by zero, sqrt or log of a negative number, ...).
#pragma once

#include <span>
#include <string>

#include "mo/symbolic/ode.hpp"

namespace mo::tools {

/// At (t, x, u, p, d): "file.mo:12:3: <source line>\n  v = <expression>\n  with a = 1, b = 0"
/// for the first assignment step whose value is not finite while its operands
/// are; the same for a block's equations when the block cannot be solved.
/// Empty when every step is finite. Never throws for a failing model.
std::string explain_non_finite(const symbolic::OdeModel& ode, double t, std::span<const double> x,
                               std::span<const double> u, std::span<const double> p,
                               std::span<const double> d);

}  // namespace mo::tools
