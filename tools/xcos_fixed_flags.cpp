// The fixed flags a diagram's model declares; see xcos_fixed_flags.hpp.
#include "xcos_fixed_flags.hpp"

#include <fstream>

#include "flat_constant.hpp"
#include "pipeline.hpp"

namespace fs = std::filesystem;

namespace mo::tools {

namespace {

std::vector<std::string> read_lines(const fs::path& file) {
  std::vector<std::string> lines;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

}  // namespace

std::string translator_name(const std::string& flat_name) {
  std::string out;
  for (std::size_t i = 0; i < flat_name.size(); ++i) {
    const char c = flat_name[i];
    if (c == '[') out += ".[";
    else if (c == ',') out += "].[";
    else if (c != ' ') out += c;
  }
  return out;
}

std::map<std::string, bool> declared_fixed_flags(const frontend::flat::Model& model) {
  std::map<std::string, bool> flags;
  for (const auto& v : model.variables) {
    if (!v.is_unknown()) continue;
    const auto value = v.attr.fixed ? constant_value(model, *v.attr.fixed) : std::optional<double>(0.0);
    if (value) flags[translator_name(v.name)] = *value != 0.0;
  }
  return flags;
}

std::optional<std::map<std::string, bool>> declared_fixed_flags(const fs::path& init_file, std::string& why) {
  const std::string name = init_file.filename().string();
  const std::string suffix = "_imf_init.xml";
  if (!name.ends_with(suffix) || name.size() == suffix.size()) {
    why = "the init file is not named <title>" + suffix;
    return std::nullopt;
  }
  const fs::path dir = init_file.parent_path();
  const fs::path model_file = dir / (name.substr(0, name.size() - suffix.size()) + "_im.mo");
  const fs::path list = dir / "translator_libs.txt";
  for (const auto& f : {model_file, list})
    if (!fs::exists(f)) {
      why = f.filename().string() + " is missing beside the init file";
      return std::nullopt;
    }
  ModelSource source{model_file.string(), "", {}, false};
  for (const auto& entry : read_lines(list)) {
    const fs::path p = fs::path(entry).is_absolute() ? fs::path(entry) : dir / entry;
    if (fs::exists(p)) source.libs.push_back(p.string());
  }
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  const auto model = load_flat_model(source, sources, diags);
  if (!model) {
    why = model_file.filename().string() + " does not flatten here" +
          (diags.all().empty() ? std::string() : ": " + diags.format(diags.all().front()));
    return std::nullopt;
  }
  return declared_fixed_flags(*model);
}

}  // namespace mo::tools
