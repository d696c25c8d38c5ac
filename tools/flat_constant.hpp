// The value of a flat expression that the flattening already knows.
#pragma once

#include <optional>

#include "mo/frontend/flat.hpp"

namespace mo::tools {

/// The value of a flat expression built from literals, parameters with known
/// values, + - * / ^, relations, and/or/not and if-expressions (Booleans as
/// 0 and 1); nullopt otherwise (also for a free parameter, whose value is
/// only a first guess).
std::optional<double> constant_value(const frontend::flat::Model& flat, const frontend::ast::Expr& e);

}  // namespace mo::tools
