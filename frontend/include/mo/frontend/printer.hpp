#pragma once
/// Printing expressions and equations as Modelica text, with the fewest
/// parentheses that keep the structure (so the text parses back to the same
/// tree), identifiers backquoted where they are not plain Modelica names.
#include "mo/frontend/ast.hpp"

#include <functional>
#include <string>

namespace mo::frontend {

/// How a flat reference (Expr::var >= 0) is printed; null prints `ref`.
using VarNamer = std::function<std::string(std::int32_t var)>;

/// `name` as it must be written in Modelica: unchanged when it is a plain
/// identifier or a 'quoted' one, otherwise inside backquotes (Xcos' dialect).
std::string quote_name(const std::string &name);

/// The Modelica text of a real number that reads back as the same double
/// (always with a '.' or exponent, e.g. `10.`, `0.5`, `1e-05`).
std::string format_real(double v);

/// Prints `e` as Modelica text.
std::string print_expr(const ast::Expr &e, const VarNamer &namer = nullptr);

/// Appends the Modelica text of `e` to `out`.
void print_expr(std::string &out, const ast::Expr &e, const VarNamer &namer = nullptr);

} // namespace mo::frontend
