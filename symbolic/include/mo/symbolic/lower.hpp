// Lowering a flat model to ODE form:
//
//   flat::Model ─ build DAE ─ alias elimination ─ Pantelides ─ dummy-derivative
//   state selection ─ matching ─ BLT ─ solve (assignments / blocks) ─ OdeModel
//
// Each stage can be dumped as text (LowerOptions::trace) for golden tests.
#pragma once

#include <optional>
#include <string>

#include "mo/frontend/diagnostics.hpp"
#include "mo/frontend/flat.hpp"
#include "mo/symbolic/ode.hpp"

namespace mo::symbolic {

/// How lowering runs and what it records.
struct LowerOptions {
  /// If set, receives a text dump of each stage: "== alias ==" (eliminated
  /// variables and their values), "== index reduction ==" (differentiated
  /// equations; states and dummy derivatives), "== blt ==" (each block with
  /// the unknowns it is matched to and its residuals), in evaluation order.
  std::string* trace = nullptr;
  /// Tear nonlinear blocks of two or more equations (docs/architecture.md,
  /// "Tearing"): Newton on a few tearing variables, the other unknowns
  /// computed from them explicitly. Off: Newton on the whole block.
  bool tearing = true;
};

/// Counts of what lowering did (for logs, benchmarks and tests).
struct LowerStats {
  std::size_t equations = 0;             ///< equations of the DAE
  std::size_t aliases = 0;               ///< variables removed by alias elimination
  std::size_t differentiated = 0;        ///< equations added by index reduction
  std::size_t dummy_derivatives = 0;     ///< differentiated variables not kept as states
};

/// Lowers `flat` to an OdeModel. On a model it cannot lower (unsupported
/// construct, structurally singular or unbalanced system, an input that would
/// need differentiating) it reports errors with source ranges to `diags` and
/// returns nullopt.
std::optional<OdeModel> lower(const frontend::flat::Model& flat,
                              frontend::DiagnosticEngine& diags,
                              const LowerOptions& options = {}, LowerStats* stats = nullptr);

}  // namespace mo::symbolic
