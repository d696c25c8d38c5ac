// The initialisation problem at t0 (Modelica 3 §8.6), lowered like the rest:
//
//   unknowns   x, der(x), y            (states, their derivatives, algebraic variables)
//   equations  the model's steps       (der(x) and y as the ODE computes them)
//              the initial equations
//              d/dt of the steps that der(y) of an initial equation needs
//              v = start(v)            for every variable declared fixed = true
//              x = start(x)            for the states the equations above leave free
//
// The last group is optional: a maximum matching admits the required
// equations first and then only as many `x = start` as it can still match
// (OpenModelica's rule for an under-determined initial system, reported as a
// warning that lists those states). A required equation that stays unmatched
// makes the system over-determined: an error naming it.
//
// The matched system is sorted into BLT blocks and solved like the model's
// equations (solve.hpp). Scalar linear blocks become closed-form expressions
// substituted into the states' start values x0(p); other blocks become
// OdeModel::initial_steps over fresh `$init(v)` symbols, which the start
// values then use. Sensitivities ∂x0/∂p differentiate through those steps
// (the implicit function theorem, as directional.hpp does for any block).
#pragma once

#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "mo/frontend/diagnostics.hpp"
#include "mo/symbolic/ode.hpp"

namespace mo::symbolic::detail {

/// One equation 0 = residual of the `initial equation` sections, over the
/// lowered model's symbols.
struct InitialEquation {
  Expr residual;
  frontend::SourceRange range;
  std::string origin;  ///< "file.mo:12:3: text" for messages, may be empty
};

/// What the initial system needs beyond the lowered model.
struct InitialInput {
  std::vector<InitialEquation> equations;
  /// Algebraic variables declared fixed = true, with their start expressions.
  std::vector<std::pair<Expr, Expr>> fixed_algebraics;
  /// First Newton guess of an unknown (state, algebraic); 0 when absent.
  std::unordered_map<Expr, double, ExprHash> guess;
  /// Unknowns whose start the model's author gave (DaeVar::start_guess:
  /// preferred tearing variables).
  std::unordered_set<Expr, ExprHash> start_guess;
  /// Tear the nonlinear blocks (LowerOptions::tearing).
  bool tearing = true;
  /// der(v) in an initial equation of a variable the model computes but does
  /// not differentiate: (placeholder symbol, v's value over the model's
  /// symbols). The initial system adds the placeholder as an unknown equal
  /// to the value's time derivative, taken through the model's steps: the
  /// derivative of every step on the way becomes an unknown with the step's
  /// differentiated equation (time_derivatives.cpp).
  std::vector<std::pair<Expr, Expr>> time_derivatives;
};

/// Replaces the states' start expressions by the solution of the initial
/// system and adds OdeModel::initial_steps. Does nothing without initial
/// equations and fixed algebraic variables (the start values are then the
/// initial state). Returns false
/// after reporting an over-determined or singular initial system.
bool lower_initial_system(OdeModel& model, const InitialInput& input,
                          frontend::DiagnosticEngine& diags);

}  // namespace mo::symbolic::detail
