// The string functions of the MSL's ModelicaExternalC (ModelicaStrings_*)
// that models call at translation, evaluated by the flattener itself on
// constant strings: the MSL's transformers take their connection letters
// from `VectorGroup` with Strings.substring. Semantics follow
// ModelicaStrings.c: indices from 1; a start index below 1, an end index
// before the start or beyond the string is an error; an end index of -999
// means the start index.
#include <fmt/format.h>

#include "flattener.hpp"

namespace mo::frontend::detail {

using ast::Expr;
using ast::ExprKind;

bool Flattener::provided_string_function(const std::string &c_name, const std::vector<const Expr *> &args,
                                         const Expr &call, const Scope &s, Tensor &out) {
  if (c_name != "ModelicaStrings_substring" && c_name != "ModelicaStrings_length")
    return false;
  auto arg = [&](std::size_t i) -> const Expr & {
    if (i >= args.size() || !args[i])
      fail(DiagId::WrongArgumentCount, call.range, fmt::format("'{}' needs argument {}", c_name, i + 1));
    return *args[i];
  };
  const std::optional<std::string> text = eval_string(*scalar_expr(arg(0), s), arg(0).range);
  if (!text)
    fail(DiagId::NotConstant, arg(0).range, "'" + c_name + "' needs a constant string, evaluated when flattening");
  if (c_name == "ModelicaStrings_length") {
    out = Tensor::scalar(ast::make_real(static_cast<double>(text->size())));
    return true;
  }
  const long long first = eval_int(arg(1), s);
  long long last = eval_int(arg(2), s);
  if (last == -999)
    last = first;
  const auto size = static_cast<long long>(text->size());
  if (first < 1)
    fail(DiagId::BadSubscript, arg(1).range, fmt::format("substring: start index {} is below 1", first));
  if (last < first)
    fail(DiagId::BadSubscript, arg(2).range,
         fmt::format("substring: end index {} is before the start index {}", last, first));
  if (last > size)
    fail(DiagId::BadSubscript, arg(2).range,
         fmt::format("substring: end index {} is beyond the string \"{}\" (length {})", last, *text, size));
  auto e = std::make_unique<Expr>(ExprKind::String, call.range);
  e->text = text->substr(static_cast<std::size_t>(first - 1), static_cast<std::size_t>(last - first + 1));
  out = Tensor::scalar(std::move(e));
  return true;
}

} // namespace mo::frontend::detail
