// An input design's full result as JSON, so that a forked worker or an MPI
// rank can hand it back: every field of runtime::InputDesignResult (the
// optimisation result with its trajectories and re-simulation check, the
// Fisher matrices and informations). Doubles round-trip exactly; NaN and
// infinities are written as the strings "nan", "inf", "-inf".
#pragma once

#include <nlohmann/json.hpp>

#include "mo/runtime/design.hpp"

namespace mo::tools {

/// The result as a JSON document.
nlohmann::json design_result_to_json(const runtime::InputDesignResult& r);

/// The inverse of design_result_to_json; throws nlohmann::json::exception on
/// a document it did not write.
runtime::InputDesignResult design_result_from_json(const nlohmann::json& j);

}  // namespace mo::tools
