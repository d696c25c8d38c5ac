// Text forms of expressions: Modelica source text (what a user would write,
// with the fewest parentheses the Modelica grammar allows) and a debug dump
// that lists each distinct node of a graph once.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <unordered_map>

#include "mo/symbolic/expr_arena.hpp"

namespace mo::symbolic {

/// `e` as a Modelica expression, e.g. "2*sin(x) + y^2". Shared subexpressions
/// are written out at each use, so the text of a DAG can be much longer than
/// the graph. Booleans print as relations; a Boolean constant prints as 0 or
/// 1. Inf and NaN print as Modelica.Constants.inf and (0.0/0.0).
/// Iterative: any depth is safe. Throws std::out_of_range for a bad handle.
std::string to_modelica(const ExprArena& arena, Expr e);

/// As to_modelica(), appending to `out`.
void append_modelica(const ExprArena& arena, Expr e, std::string& out);

/// Names that stand for subexpressions in printed text (print_ode() names
/// the large shared ones).
using ExprNames = std::unordered_map<Expr, std::string, ExprHash>;

/// As append_modelica(), writing each node of `names` other than `e` itself
/// as its name: `e`'s definition when `e` is in `names`.
void append_modelica(const ExprArena& arena, Expr e, std::string& out, const ExprNames& names);

/// `name` as Modelica text: unchanged if it is a component reference such as
/// `a.b[2].c` (no keywords), otherwise a quoted identifier such as 'my var'.
std::string modelica_name(std::string_view name);

/// One line per distinct node reachable from `outputs` in topological order,
/// e.g. "%4 = Mul(%2, %3)", "%1 = phi (State 1)", then "out[0] = %4".
std::string dump_graph(const ExprArena& arena, std::span<const Expr> outputs);

} // namespace mo::symbolic
