#include "xcos_init.hpp"
#include "xcos_diagram.hpp"

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

std::vector<std::string> apply_init_file(frontend::flat::Model& model, const std::vector<InitTerminal>& terminals) {
  std::vector<std::string> fixed;
  for (const auto& t : terminals) {
    if (t.kind != "variable" || t.fixed != "true") continue;
    const auto index = model.find(t.id);
    if (index < 0) continue;  // e.g. the translator's __der_ entries
    auto& v = model.variables[static_cast<std::size_t>(index)];
    if (!v.is_unknown()) continue;
    if (!v.attr.start) {
      const auto value = literal(t.initial_value);
      if (!value) continue;  // no start value to fix the variable to
      v.attr.start = frontend::ast::make_real(*value);
    }
    v.attr.fixed = frontend::ast::make_bool(true);
    fixed.push_back(v.name);
  }
  return fixed;
}

std::string apply_diagram_init(frontend::flat::Model& model, const fs::path& file, const std::string& tool) {
  if (file.empty()) return {};
  std::vector<InitTerminal> terminals;
  try {
    terminals = read_init_file(file);
  } catch (const std::runtime_error& e) {
    throw DiagramError(e.what());
  }
  const auto fixed = apply_init_file(model, terminals);
  if (fixed.empty()) return {};
  std::string names;
  for (std::size_t i = 0; i < fixed.size() && i < 8; ++i) names += (i ? ", " : "") + fixed[i];
  if (fixed.size() > 8) names += fmt::format(" and {} more", fixed.size() - 8);
  return fmt::format("{}: note: the diagram's init file fixes the start value of {} variable{}: {}", tool,
                     fixed.size(), fixed.size() == 1 ? "" : "s", names);
}

}  // namespace mo::tools
