// Parse, flatten, lower; see pipeline.hpp.
#include "pipeline.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "mo/frontend/flatten.hpp"
#include "mo/frontend/parser.hpp"
#include "mo/symbolic/sensitivities.hpp"

#include "mo/symbolic/evaluator.hpp"
#include "mo/symbolic/ode_interpreter.hpp"
#include "mo/symbolic/lower.hpp"

namespace fs = std::filesystem;

namespace mo::tools {

std::vector<std::string> library_files(const std::string& arg) {
  std::vector<std::string> files;
  std::error_code ec;
  if (fs::is_directory(arg, ec)) {
    for (auto& entry : fs::recursive_directory_iterator(arg, ec))
      if (entry.is_regular_file() && entry.path().extension() == ".mo")
        files.push_back(entry.path().string());
    std::sort(files.begin(), files.end(), [](const std::string& a, const std::string& b) {
      bool pa = fs::path(a).filename() == "package.mo", pb = fs::path(b).filename() == "package.mo";
      auto da = std::count(a.begin(), a.end(), '/'), db = std::count(b.begin(), b.end(), '/');
      return std::tie(da, pb, a) < std::tie(db, pa, b);
    });
  } else {
    files.push_back(arg);
  }
  return files;
}

void load_libraries(frontend::Library& lib, const std::vector<std::string>& libs,
                    const std::string& main_file, frontend::SourceManager& sources,
                    frontend::DiagnosticEngine& diags) {
  lib.enable_loading(sources, diags);
  for (const auto& arg : libs) {
    std::error_code ec;
    if (fs::is_directory(arg, ec) && fs::is_regular_file(fs::path(arg) / "package.mo", ec)) {
      lib.add_package_directory(arg);  // parse errors are in diags
      continue;
    }
    for (const auto& file : library_files(arg))
      if (auto sd = frontend::parse_file(file, sources, diags)) lib.add(std::move(sd));
  }
  const fs::path dir = fs::path(main_file).parent_path();
  lib.add_search_root(dir.empty() ? std::string(".") : dir.string());
  if (const char* path = std::getenv("MODELICAPATH")) {
    std::string entry;
    for (const char* c = path;; ++c) {
      if (*c == ':' || *c == ';' || *c == '\0') {
        if (!entry.empty()) lib.add_search_root(entry);
        entry.clear();
        if (*c == '\0') break;
      } else {
        entry += *c;
      }
    }
  }
}

std::unique_ptr<frontend::flat::Model> load_flat_model(const ModelSource& source,
                                                       frontend::SourceManager& sources,
                                                       frontend::DiagnosticEngine& diags) {
  using namespace mo::frontend;
  Library lib;
  load_libraries(lib, source.libs, source.file, sources, diags);
  auto main_file = parse_file(source.file, sources, diags);
  if (!main_file || diags.has_errors()) return nullptr;
  std::string class_name = source.class_name;
  if (class_name.empty() && !main_file->classes.empty()) {
    for (const auto& part : main_file->within) class_name += part + ".";
    class_name += main_file->classes.back()->name;
  }
  lib.add(std::move(main_file));
  FlattenOptions fo;
  fo.check_balance = source.check_balance;
  return flatten(lib, class_name, diags, fo);
}

std::optional<symbolic::OdeModel> lower_model(const frontend::flat::Model& flat,
                                              frontend::DiagnosticEngine& diags,
                                              std::string* trace) {
  symbolic::LowerOptions options;
  options.trace = trace;
  return symbolic::lower(flat, diags, options);
}

void expose_start_parameters(symbolic::OdeModel& model, const std::vector<std::string>& names) {
  for (const std::string& raw : names) {
    const std::string name = raw.substr(0, raw.find('='));
    if (!name.ends_with(".start") || model.parameter_index(name)) continue;
    const auto x = model.state_index(name.substr(0, name.size() - 6));
    if (!x) continue;
    std::vector<double> defaults;
    for (const auto& p : model.parameters) defaults.push_back(p.value);
    // Through the initial system, if any; the parameter then replaces its solution.
    const double value = symbolic::OdeInterpreter(model).initial_state(defaults)[*x];
    symbolic::OdeState& state = model.states[*x];
    symbolic::OdeParameter p;
    p.info.name = name;
    p.info.description = "start value of " + state.info.name;
    p.info.unit = state.info.unit;
    p.value = value;
    p.symbol = model.arena.symbol(name, symbolic::SymbolRole::Parameter,
                                  static_cast<std::int32_t>(model.parameters.size()));
    state.start = p.symbol;
    model.parameters.push_back(std::move(p));
  }
}

std::string add_named_sensitivities(symbolic::OdeModel& model, const std::vector<std::string>& names) {
  std::vector<std::size_t> indices;
  for (const auto& n : names) {
    const auto k = model.parameter_index(n);
    if (!k) {
      std::string known;
      for (const auto& p : model.parameters) known += (known.empty() ? "" : ", ") + p.info.name;
      return "--sensitivities: '" + n + "' is not a parameter of " + model.name +
             (known.empty() ? " (it has none)" : " (parameters: " + known + ")");
    }
    indices.push_back(*k);
  }
  if (!indices.empty()) symbolic::add_sensitivities(model, indices);
  return {};
}

}  // namespace mo::tools
