// Turning untrusted model text into C++ source text. Nothing from a model
// reaches generated code except through these functions: names and comments
// become escaped string literals, identifiers are mapped to [A-Za-z0-9_].
#pragma once

#include <set>
#include <string>
#include <string_view>

namespace mo::codegen {

/// `text` as a C++ string literal, quotes included, e.g. "a\"b". Escapes
/// quotes and backslashes; writes '?' as \? (no trigraphs); '/' after '*' as
/// \057 (no comment end); control characters and bytes >= 0x7f as 3-digit
/// octal escapes (so a following digit is never absorbed). Byte-exact.
std::string cpp_string_literal(std::string_view text);

/// `v` as a C++ expression of type double that round-trips exactly
/// (infinities and NaN through std::numeric_limits; negatives parenthesised).
std::string cpp_double(double v);

/// True if `s` is a valid C++ identifier that is not a keyword and not
/// reserved (no "__", no leading underscore).
bool is_cpp_identifier(std::string_view s);

/// A valid identifier derived from `name` ('.' and other characters become
/// '_', keywords get a trailing '_', "v_" prefixed if needed) that is not in
/// `used`; the result is inserted into `used`.
std::string cpp_identifier(std::string_view name, std::set<std::string>& used);

}  // namespace mo::codegen
