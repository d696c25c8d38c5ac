// mocompile: Modelica → AST / flat Modelica (and, as later stages land,
// the lowered ODE and C++). Exit status: 0 success, 1 errors in the model,
// 2 bad command line.
#include "mo/frontend/flatten.hpp"
#include "mo/frontend/parser.hpp"
#include "mo/runtime/result.hpp"
#include "mo/symbolic/lower.hpp"
#include "mo/symbolic/sensitivities.hpp"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>

namespace fs = std::filesystem;
using namespace mo::frontend;

namespace {

struct Options {
  std::string input;
  std::string class_name;
  std::vector<std::string> libs;
  std::string emit = "flat";
  std::string output;
  bool no_balance_check = false;
  unsigned max_errors = 50;
  std::vector<std::string> sensitivities;
};

/// The .mo files of a library argument: the file itself, or every .mo file
/// under a directory (package.mo files first, so `within` packages exist).
std::vector<std::string> library_files(const std::string &arg) {
  std::vector<std::string> files;
  std::error_code ec;
  if (fs::is_directory(arg, ec)) {
    for (auto &entry : fs::recursive_directory_iterator(arg, ec))
      if (entry.is_regular_file() && entry.path().extension() == ".mo")
        files.push_back(entry.path().string());
    std::sort(files.begin(), files.end(), [](const std::string &a, const std::string &b) {
      bool pa = fs::path(a).filename() == "package.mo", pb = fs::path(b).filename() == "package.mo";
      auto da = std::count(a.begin(), a.end(), '/'), db = std::count(b.begin(), b.end(), '/');
      return std::tie(da, pb, a) < std::tie(db, pa, b);
    });
  } else {
    files.push_back(arg);
  }
  return files;
}

/// Lowers a flat model and appends the requested sensitivities; nullopt after
/// reporting errors (unknown parameter names included) to `diags`.
std::optional<mo::symbolic::OdeModel> lower_model(const flat::Model &model, const Options &opt,
                                                  DiagnosticEngine &diags) {
  mo::symbolic::LowerOptions lo;
  std::string trace;
  if (opt.emit == "trace") lo.trace = &trace;
  auto ode = mo::symbolic::lower(model, diags, lo);
  if (lo.trace) std::cout << trace;
  if (!ode) return std::nullopt;
  std::vector<std::size_t> params;
  for (const auto &name : opt.sensitivities) {
    if (auto k = ode->parameter_index(name)) {
      params.push_back(*k);
      continue;
    }
    std::string known;
    for (const auto &p : ode->parameters) known += (known.empty() ? "" : ", ") + p.info.name;
    diags.report(DiagId::UnknownComponent, {},
                 "--sensitivities: '" + name + "' is not a parameter of " + model.name +
                     (known.empty() ? " (it has none)" : " (parameters: " + known + ")"));
    return std::nullopt;
  }
  if (!params.empty()) mo::symbolic::add_sensitivities(*ode, params);
  return ode;
}

int run(const Options &opt) {
  SourceManager sources;
  DiagnosticEngine diags(sources, opt.max_errors);
  Library lib;
  for (const auto &arg : opt.libs)
    for (const auto &file : library_files(arg))
      if (auto sd = parse_file(file, sources, diags))
        lib.add(std::move(sd));
  auto main_file = parse_file(opt.input, sources, diags);
  if (!main_file || diags.has_errors()) {
    diags.print(std::cerr);
    return 1;
  }
  std::string text;
  std::string class_name = opt.class_name;
  if (class_name.empty() && !main_file->classes.empty()) {
    for (const auto &part : main_file->within) class_name += part + ".";
    class_name += main_file->classes.back()->name;
  }
  if (opt.emit == "ast") {
    text = ast::dump(*main_file);
  } else {
    lib.add(std::move(main_file));
    FlattenOptions fo;
    fo.check_balance = !opt.no_balance_check;
    auto model = flatten(lib, class_name, diags, fo);
    if (!model) {
      diags.print(std::cerr);
      return 1;
    }
    if (opt.emit == "flat") {
      text = model->print();
    } else if (auto ode = lower_model(*model, opt, diags)) {
      text = mo::symbolic::print_ode(*ode);
    } else {
      diags.print(std::cerr);
      return 1;
    }
  }
  diags.print(std::cerr); // warnings
  if (opt.output.empty() || opt.output == "-") {
    std::cout << text;
    return 0;
  }
  try {
    mo::runtime::write_file_atomic(opt.output, [&](std::ostream &os) { os << text; });
  } catch (const std::exception &e) {
    std::cerr << "mocompile: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

} // namespace

int main(int argc, char **argv) {
  CLI::App app{"mocompile — compile a Modelica model: parse, flatten, and print a stage's IR.\n"
               "Reads hierarchical Modelica, Optimica and the flat Modelica that Scilab/Xcos writes."};
  app.set_version_flag("--version", "mocompile 0.1.0");
  Options opt;
  app.add_option("file", opt.input, "Modelica file (.mo, .mop, .opt) holding the class to compile")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("-c,--class", opt.class_name,
                 "Class to instantiate, as a dotted path (default: the last class in FILE)");
  app.add_option("-L,--library", opt.libs,
                 "Library file or directory of .mo files to load before FILE (repeatable)")
      ->check(CLI::ExistingPath);
  app.add_option("--emit", opt.emit,
                 "What to print: 'ast' (the parsed file), 'flat' (the flattened model) or 'ode' "
                 "(the lowered model: states, ordered assignments and blocks), as Modelica; 'trace' "
                 "prints each lowering stage (alias, index reduction, BLT) before the ode")
      ->check(CLI::IsMember({"ast", "flat", "ode", "trace"}))
      ->capture_default_str();
  app.add_option("--sensitivities", opt.sensitivities,
                 "Append forward sensitivity equations for these parameters (comma-separated); "
                 "implies --emit ode unless another lowered output is chosen")
      ->delimiter(',');
  app.add_option("-o,--output", opt.output, "Write the result to this file (atomically) instead of stdout");
  app.add_flag("--no-balance-check", opt.no_balance_check,
               "Do not check that the model has as many equations as unknowns");
  app.add_option("--max-errors", opt.max_errors, "Stop listing errors after this many")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (!opt.sensitivities.empty() && opt.emit == "flat") opt.emit = "ode";
  try {
    return run(opt);
  } catch (const std::exception &e) {
    std::cerr << "mocompile: internal error: " << e.what() << "\n";
    return 3;
  }
}
