// The string functions of the MSL's ModelicaExternalC (ModelicaStrings_*)
// that models call at translation, evaluated by the flattener itself on
// constant strings: the MSL's transformers take their connection letters
// from `VectorGroup` with Strings.substring. Semantics follow
// ModelicaStrings.c: indices from 1, an end index beyond the string or a
// start index below 1 is an error, an end before the start gives "".
#include <fmt/format.h>

#include "flattener.hpp"

namespace mo::frontend::detail {

using ast::Expr;
using ast::ExprKind;
using ast::ExprPtr;

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
  const long long first = eval_int(arg(1), s), last = eval_int(arg(2), s);
  const auto size = static_cast<long long>(text->size());
  if (first < 1 || first > size)
    fail(DiagId::BadSubscript, arg(1).range,
         fmt::format("substring: start index {} is outside the string \"{}\" (1 to {})", first, *text, size));
  if (last > size)
    fail(DiagId::BadSubscript, arg(2).range,
         fmt::format("substring: end index {} is beyond the string \"{}\" (length {})", last, *text, size));
  auto e = std::make_unique<Expr>(ExprKind::String, call.range);
  if (last >= first)
    e->text = text->substr(static_cast<std::size_t>(first - 1), static_cast<std::size_t>(last - first + 1));
  out = Tensor::scalar(std::move(e));
  return true;
}

} // namespace mo::frontend::detail
