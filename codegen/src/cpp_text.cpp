// Escaping and identifier mapping; see cpp_text.hpp.
#include "mo/codegen/cpp_text.hpp"

#include <array>
#include <cmath>
#include <fmt/format.h>

namespace mo::codegen {

namespace {

constexpr std::array<std::string_view, 97> keywords = {
    "alignas", "alignof", "and", "and_eq", "asm", "auto", "bitand", "bitor", "bool", "break",
    "case", "catch", "char", "char8_t", "char16_t", "char32_t", "class", "compl", "concept",
    "const", "consteval", "constexpr", "constinit", "const_cast", "continue", "co_await",
    "co_return", "co_yield", "decltype", "default", "delete", "do", "double", "dynamic_cast",
    "else", "enum", "explicit", "export", "extern", "false", "float", "for", "friend", "goto",
    "if", "inline", "int", "long", "mutable", "namespace", "new", "noexcept", "not", "not_eq",
    "nullptr", "operator", "or", "or_eq", "private", "protected", "public", "register",
    "reinterpret_cast", "requires", "return", "short", "signed", "sizeof", "static",
    "static_assert", "static_cast", "struct", "switch", "template", "this", "thread_local",
    "throw", "true", "try", "typedef", "typeid", "typename", "union", "unsigned", "using",
    "virtual", "void", "volatile", "wchar_t", "while", "xor", "xor_eq", "final", "override",
    "import", "module", "std"};

bool is_keyword(std::string_view s) {
  for (auto k : keywords)
    if (k == s) return true;
  return false;
}

bool identifier_char(char c, bool first) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' ||
         (!first && c >= '0' && c <= '9');
}

}  // namespace

std::string cpp_string_literal(std::string_view text) {
  std::string out = "\"";
  out.reserve(text.size() + 2);
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    switch (c) {
    case '"': out += "\\\""; continue;
    case '\\': out += "\\\\"; continue;
    case '\n': out += "\\n"; continue;
    case '\t': out += "\\t"; continue;
    case '?': out += "\\?"; continue;
    default: break;
    }
    const bool comment_end = c == '/' && i > 0 && text[i - 1] == '*';
    if (c < 0x20 || c >= 0x7f || comment_end)
      out += fmt::format("\\{:03o}", c);
    else
      out += static_cast<char>(c);
  }
  return out + "\"";
}

std::string cpp_double(double v) {
  if (std::isnan(v)) return "std::numeric_limits<double>::quiet_NaN()";
  if (std::isinf(v))
    return v > 0 ? "std::numeric_limits<double>::infinity()"
                 : "(-std::numeric_limits<double>::infinity())";
  std::string s = fmt::format("{}", v);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return v < 0 || std::signbit(v) ? "(" + s + ")" : s;
}

bool is_cpp_identifier(std::string_view s) {
  if (s.empty() || s.front() == '_' || s.find("__") != std::string_view::npos || is_keyword(s))
    return false;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (!identifier_char(s[i], i == 0)) return false;
  return true;
}

std::string cpp_identifier(std::string_view name, std::set<std::string>& used) {
  std::string id;
  for (char c : name) {
    const char m = identifier_char(c, false) ? c : '_';
    if (m == '_' && (id.empty() || id.back() == '_')) continue;  // no leading or double '_'
    id += m;
  }
  while (!id.empty() && id.back() == '_') id.pop_back();
  if (id.empty() || !identifier_char(id.front(), true)) id = "v_" + id;
  if (is_keyword(id)) id += "_";
  std::string candidate = id;
  for (int k = 2; used.contains(candidate); ++k) candidate = id + "_" + std::to_string(k);
  used.insert(candidate);
  return candidate;
}

}  // namespace mo::codegen
