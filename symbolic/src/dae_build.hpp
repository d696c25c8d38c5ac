// flat::Model → Dae: symbols for unknowns, parameters, inputs and discrete
// variables; residuals for equations; when-clauses. Reports what lowering
// does not support with the source range of the construct.
#pragma once

#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "dae.hpp"
#include "mo/symbolic/evaluator.hpp"
#include "mo/frontend/diagnostics.hpp"
#include "mo/frontend/flat.hpp"

namespace mo::symbolic::detail {

/// Builds the DAE of `flat`; nullopt after reporting errors to `diags`.
std::optional<Dae> build_dae(const frontend::flat::Model& flat, frontend::DiagnosticEngine& diags);

class ExprConverter;

/// An initial equation on pre() values, `lhs = rhs`: `pre(v) = expr`, or
/// `v = expr` for a v that equals an expression of pre() values (InitialStep
/// of the MSL's StateGraph: `active = true` with `active = pre(newActive)`).
struct PreEquation {
  Expr lhs, rhs;
  frontend::SourceRange range;
};

/// Modelica 3 §8.6: the pre() values of discrete variables are unknowns of
/// the initial system. Solves `eqs` for those they read, in any order: an
/// equation left with one open value is solved for it (a side that is that
/// value; a Boolean that one of false and true satisfies); when none is, the
/// first one with a side that is an open value defines it and the others it
/// reads keep their start values. Sets dae.discrete[i].start to each solved
/// value. `at_t0` holds the parameters' values and time = t0; `boolean[i]`
/// says whether dae.discrete[i] is a Boolean. False after a diagnostic (a
/// contradiction, or a value that does not follow). Variables that explicit
/// equations give from the values of `at_t0` alone count as known.
bool solve_initial_pre(Dae& dae, const std::vector<PreEquation>& eqs, const LeafValues& at_t0,
                       const std::vector<bool>& boolean, frontend::DiagnosticEngine& diags);

/// The discrete flag of `call`, a flat `sample(start, interval)`: one per
/// distinct (start, interval), added to dae.discrete and dae.samples on first
/// use. The interval must be a parameter expression, positive at
/// `parameters` (the parameters' values); the start may also read
/// `computed`, the variables of parameters that the initial equations compute
/// (the MSL's Mean: `sample(t0 + 1/f, 1/f)` with `t0 = time` at
/// initialisation). Otherwise reported through `conv` (converts to 0).
Expr sample_flag(Dae& dae, ExprConverter& conv, const frontend::ast::Expr& call,
                 const std::unordered_map<Expr, double, ExprHash>& parameters,
                 const std::unordered_set<Expr, ExprHash>& computed);

/// Marks the variables whose der() the (alias-reduced) equations contain
/// (DaeVar::source_derivative), and those among them with a time-invariant
/// coefficient in some equation (DaeVar::linear_derivative). Run before
/// index reduction adds derivatives of its own (source_states.cpp).
void mark_source_derivatives(Dae& dae);

/// d/dt of `e`: every variable v with DAE index maps to der(v) (created on
/// demand), time to 1; parameters, discrete variables and constants to 0.
/// Inputs cannot be differentiated: `input_hit` is set if one is reached.
/// `initial` (an initial equation): a variable the model does not
/// differentiate maps to its placeholder (Dae::initial_derivatives) instead.
Expr time_derivative(Dae& dae, Expr e, bool& input_hit, bool initial = false);

}  // namespace mo::symbolic::detail
