// Derivatives of a model's event map, for sensitivities through events.
//
// At an event at time τ with indicator g(x, u, p, t) = 0 the state jumps,
// x⁺ = r(x⁻, u, p, t) (r the when-clauses' reinits, identity elsewhere). Along
// a direction (δx, δu, δp, δt) of (x⁻, u(τ), p, τ) this gives
//
//   δg = g_x δx + g_u δu + g_p δp + g_t δt   (one expression per indicator)
//   δr = r_x δx + r_u δu + r_p δp + r_t δt   (one per reinit and discrete assignment)
//
// through the steps by the chain rule (directional.hpp), with pre(v) of a
// continuous v moving like v. The run time uses them with δu = u̇ δt:
//   dτ/dp = −(g_x S⁻ + g_p) / (g_x f⁻ + g_u u̇ + g_t)   (δ = (S⁻, 0, e_p, 0) and (f⁻, u̇, 0, 1))
//   S⁺    = δr[S⁻ + f⁻ dτ/dp, u̇ dτ/dp, e_p, dτ/dp] − f⁺ dτ/dp
// which is r_x S⁻ + r_p + (r_x f⁻ + r_u u̇ + r_t − f⁺) dτ/dp. Discrete
// variables are held fixed along the direction, except those that have
// discrete sensitivities (OdeDiscrete::sensitivity): they move by δd = their
// sensitivity, and pre(d) with them.
#pragma once

#include <vector>

#include "mo/symbolic/directional.hpp"

namespace mo::symbolic {

/// The tangent of one when-clause's effect.
struct WhenTangent {
  std::vector<Expr> assignments;  ///< δ(value) per assignment, in the clause's order
  std::vector<Expr> reinits;      ///< δ(value) per reinit, in the clause's order
};

/// The event map's derivatives along the seed direction.
struct EventTangents {
  std::vector<Expr> seed_x;  ///< δx, one symbol per state
  std::vector<Expr> seed_u;  ///< δu, one symbol per input
  std::vector<Expr> seed_p;  ///< δp, one symbol per parameter
  /// δd per discrete variable: a symbol for those that have discrete
  /// sensitivities, an invalid Expr for the others (held fixed).
  std::vector<Expr> seed_d;
  Expr seed_t;               ///< δt
  Directional directional;   ///< steps computing the step targets' derivatives
  std::vector<Expr> indicators;  ///< δg per zero crossing
  std::vector<WhenTangent> whens;  ///< per when-clause
  /// δstart and δinterval per sample(): a tick start + k·interval moves by
  /// δstart + k·δinterval.
  std::vector<Expr> sample_starts, sample_intervals;
};

/// Builds the event tangents of `model` in model.arena (seed symbols are new
/// Algebraic symbols named "$event_seed..."); the model is not changed otherwise.
EventTangents event_tangents(OdeModel& model);

/// Per discrete variable: true if a when-clause assigns it a value whose
/// derivative along states, inputs, parameters and time (and such discrete variables,
/// to a fixed point) is not structurally zero — a sample-and-hold `u = -k*x`,
/// not a mode flag `if x > 0 then 1 else 2`. Adds seed symbols to the arena.
std::vector<bool> discrete_with_tangents(OdeModel& model);

}  // namespace mo::symbolic
