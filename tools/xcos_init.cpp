#include "xcos_init.hpp"
#include "xcos_diagram.hpp"
#include "xcos_fixed_flags.hpp"

#include <expat.h>

#include <cstdlib>
#include <fstream>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

namespace fs = std::filesystem;

namespace mo::tools {

namespace {

constexpr std::uintmax_t kMaxBytes = std::uintmax_t{256} << 20;

/// The element being read, as far as it matters.
enum class Field { None, Kind, Id };

/// Expat callbacks' state: the current <terminal>, the text field being collected.
struct Reader {
  XML_Parser parser = nullptr;
  std::vector<InitTerminal> terminals;
  bool in_terminal = false;
  InitTerminal current;
  Field field = Field::None;
  std::string error;  ///< set by a handler that stopped the parser
};

std::string attribute(const XML_Char** attrs, const char* name) {
  for (std::size_t i = 0; attrs[i] != nullptr; i += 2)
    if (std::string(attrs[i]) == name) return attrs[i + 1];
  return {};
}

void on_start(void* data, const XML_Char* name, const XML_Char** attrs) {
  auto& r = *static_cast<Reader*>(data);
  const std::string element = name;
  if (element == "terminal") {
    r.in_terminal = true;
    r.current = {};
    return;
  }
  if (!r.in_terminal) return;
  if (element == "kind") r.field = Field::Kind;
  else if (element == "id") r.field = Field::Id;
  else if (element == "fixed") r.current.fixed = attribute(attrs, "value");
  else if (element == "initial_value") r.current.initial_value = attribute(attrs, "value");
}

void on_end(void* data, const XML_Char* name) {
  auto& r = *static_cast<Reader*>(data);
  const std::string element = name;
  r.field = Field::None;
  if (element == "terminal" && r.in_terminal) {
    r.in_terminal = false;
    r.terminals.push_back(std::move(r.current));
  }
}

void on_text(void* data, const XML_Char* text, int length) {
  auto& r = *static_cast<Reader*>(data);
  switch (r.field) {
    case Field::None: return;
    case Field::Kind: r.current.kind.append(text, static_cast<std::size_t>(length)); return;
    case Field::Id: r.current.id.append(text, static_cast<std::size_t>(length)); return;
  }
}

/// Scilab's init files have no DTD; one (and with it entity definitions) is refused.
void on_doctype(void* data, const XML_Char*, const XML_Char*, const XML_Char*, int) {
  auto& r = *static_cast<Reader*>(data);
  r.error = "a document type declaration (DTD) is not expected in an init file";
  XML_StopParser(r.parser, XML_FALSE);
}

std::string trimmed(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}

/// A plain number as Scilab writes it ("0.", "4.", "(-1.)", "1e-05"), or nullopt.
std::optional<double> literal(std::string text) {
  text = trimmed(text);
  if (text.size() > 2 && text.front() == '(' && text.back() == ')') text = text.substr(1, text.size() - 2);
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return std::nullopt;
  return v;
}

/// "N variable(s): a, b, ... and K more".
std::string listed(const std::vector<std::string>& names) {
  std::string text = fmt::format("{} variable{}: ", names.size(), names.size() == 1 ? "" : "s");
  for (std::size_t i = 0; i < names.size() && i < 8; ++i) text += (i ? ", " : "") + names[i];
  if (names.size() > 8) text += fmt::format(" and {} more", names.size() - 8);
  return text;
}

}  // namespace

std::vector<InitTerminal> read_init_file(const fs::path& file) {
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  if (ec) throw std::runtime_error(file.string() + ": error: cannot read the init file: " + ec.message());
  if (size > kMaxBytes) throw std::runtime_error(file.string() + ": error: the init file is larger than 256 MB");
  std::ifstream in(file, std::ios::binary);
  std::string text(static_cast<std::size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (!in) throw std::runtime_error(file.string() + ": error: cannot read the init file");

  Reader r;
  std::unique_ptr<XML_ParserStruct, decltype(&XML_ParserFree)> parser(XML_ParserCreate("UTF-8"), &XML_ParserFree);
  if (!parser) throw std::runtime_error("cannot create an XML parser");
  r.parser = parser.get();
  XML_SetUserData(r.parser, &r);
  XML_SetElementHandler(r.parser, on_start, on_end);
  XML_SetCharacterDataHandler(r.parser, on_text);
  XML_SetStartDoctypeDeclHandler(r.parser, on_doctype);
  XML_SetParamEntityParsing(r.parser, XML_PARAM_ENTITY_PARSING_NEVER);
  if (XML_Parse(r.parser, text.data(), static_cast<int>(text.size()), XML_TRUE) != XML_STATUS_OK) {
    const std::string why = r.error.empty() ? XML_ErrorString(XML_GetErrorCode(r.parser)) : r.error;
    throw std::runtime_error(fmt::format("{}:{}: error: {}", file.string(),
                                         XML_GetCurrentLineNumber(r.parser), why));
  }
  for (auto& t : r.terminals) {
    t.id = trimmed(t.id);
    t.kind = trimmed(t.kind);
  }
  return std::move(r.terminals);
}

InitFlags apply_init_file(frontend::flat::Model& model, const std::vector<InitTerminal>& terminals,
                          const std::map<std::string, bool>* declared) {
  InitFlags out;
  for (const auto& t : terminals) {
    if (t.kind != "variable" || t.fixed != "true") continue;
    const auto index = model.find(t.id);
    if (index < 0) continue;  // e.g. the translator's __der_ entries
    auto& v = model.variables[static_cast<std::size_t>(index)];
    if (!v.is_unknown()) continue;
    if (declared)
      if (const auto it = declared->find(t.id); it != declared->end() && !it->second) {
        out.not_declared.push_back(v.name);
        continue;
      }
    if (!v.attr.start) {
      const auto value = literal(t.initial_value);
      if (!value) continue;  // no start value to fix the variable to
      v.attr.start = frontend::ast::make_real(*value);
    }
    v.attr.fixed = frontend::ast::make_bool(true);
    out.fixed.push_back(v.name);
  }
  return out;
}

std::string apply_diagram_init(frontend::flat::Model& model, const fs::path& file, const std::string& tool) {
  if (file.empty()) return {};
  std::vector<InitTerminal> terminals;
  try {
    terminals = read_init_file(file);
  } catch (const std::runtime_error& e) {
    throw DiagramError(e.what());
  }
  std::string why, lines;
  const auto declared = declared_fixed_flags(file, why);
  if (!declared)
    lines = fmt::format("{}: warning: the init file's fixed flags are taken as they are, unchecked ({}); the "
                        "translator marks fixed every variable whose fixed attribute depends on a block "
                        "parameter\n",
                        tool, why);
  const InitFlags flags = apply_init_file(model, terminals, declared ? &*declared : nullptr);
  if (!flags.not_declared.empty())
    lines += fmt::format("{}: note: the init file marks fixed, but the model does not fix with the diagram's "
                         "parameters (Scilab's translator marks every fixed attribute that depends on a block "
                         "parameter), {}: left free\n",
                         tool, listed(flags.not_declared));
  if (!flags.fixed.empty())
    lines += fmt::format("{}: note: the diagram's init file fixes the start value of {}\n", tool,
                         listed(flags.fixed));
  if (!lines.empty()) lines.pop_back();
  return lines;
}

}  // namespace mo::tools
