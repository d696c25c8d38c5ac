// mocompile: Modelica → AST / flat Modelica (and, as later stages land,
// the lowered ODE and C++). Exit status: 0 success, 1 errors in the model,
// 2 bad command line.
#include "mo/frontend/flatten.hpp"
#include "mo/frontend/parser.hpp"
#include "mo/codegen/cpp_text.hpp"
#include "mo/codegen/generate.hpp"
#include "mo/runtime/result.hpp"
#include "mo/symbolic/lower.hpp"
#include "pipeline.hpp"
#include "progress.hpp"
#include "xcos_init.hpp"
#include "diagram_cli.hpp"

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>

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
  std::string cpp_name = "mo_model";       // --emit cpp: namespace and file stem
  std::vector<std::string> sensitivities;  // --emit ode|trace|cpp: parameters
  std::size_t cpp_files = 0;               // --emit cpp: exact number of part files (0: as needed)
  mo::tools::DiagramOptions diagram;       // FILE is an Xcos diagram: how to run Scilab
  bool from_diagram = false;               // input is the flat file Scilab wrote for it
  bool quiet = false;                      // no progress on stderr
  std::string init_file;                   // the diagram's <title>_imf_init.xml, or empty
};

/// Lowers, printing the stage trace for --emit trace, and appends the
/// requested sensitivities; nullopt after printing the errors, with `status`
/// set to 1 (errors in the model) or 2 (an unknown --sensitivities name).
std::optional<mo::symbolic::OdeModel> lowered(const flat::Model &model, DiagnosticEngine &diags,
                                              const Options &opt, int &status, mo::tools::RunContext &ctx) {
  status = 1;
  std::string trace;
  std::optional<mo::symbolic::OdeModel> ode;
  {
    mo::tools::PhaseScope phase(&ctx, "lower", model.name);
    ode = mo::tools::lower_model(model, diags, opt.emit == "trace" ? &trace : nullptr);
  }
  std::cout << trace;
  if (!ode) {
    diags.print(std::cerr);
    return std::nullopt;
  }
  mo::tools::expose_start_parameters(*ode, opt.sensitivities);  // x.start
  std::string error;
  {
    mo::tools::PhaseScope phase(&ctx, "sensitivities", model.name);
    error = mo::tools::add_named_sensitivities(*ode, opt.sensitivities);
  }
  if (!error.empty()) {
    std::cerr << "mocompile: error: " << error << "\n";
    status = 2;  // a command-line mistake, as in morun
    return std::nullopt;
  }
  return ode;
}

/// --emit cpp: generate C++ and write the files into the directory
/// opt.output (each file atomically).
int emit_cpp(mo::symbolic::OdeModel &ode, DiagnosticEngine &diags, const Options &opt,
             mo::tools::RunContext &ctx) {
  std::optional<mo::tools::PhaseScope> phase(std::in_place, &ctx, "generate", opt.cpp_name);
  mo::codegen::CodegenOptions co;
  co.name = opt.cpp_name;
  co.part_files = opt.cpp_files;
  const auto sources = mo::codegen::generate_cpp(ode, co);
  phase.reset();
  diags.print(std::cerr);  // warnings
  fs::create_directories(opt.output);
  for (const auto &file : sources.files)
    mo::runtime::write_file_atomic((fs::path(opt.output) / file.path).string(),
                                   [&](std::ostream &os) { os << file.text; });
  return 0;
}

int run(const Options &opt, mo::tools::RunContext &ctx) {
  std::optional<mo::tools::PhaseScope> parsing(std::in_place, &ctx, "flatten", opt.input);
  SourceManager sources;
  DiagnosticEngine diags(sources, opt.max_errors);
  Library lib;
  mo::tools::load_libraries(lib, opt.libs, opt.input, sources, diags);
  auto main_file = parse_file(opt.input, sources, diags);
  if (!main_file || diags.has_errors()) {
    parsing.reset();
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
    parsing.reset();
  } else {
    lib.add(std::move(main_file));
    FlattenOptions fo;
    fo.check_balance = !opt.no_balance_check;
    auto model = flatten(lib, class_name, diags, fo);
    parsing.reset();
    if (!model) {
      diags.print(std::cerr);
      return 1;
    }
    if (opt.from_diagram) {
      if (const auto note = mo::tools::apply_diagram_init(*model, opt.init_file, "mocompile"); !note.empty())
        std::cerr << note << "\n";
      if (const auto note = mo::tools::diagram_inputs_note(*model, "mocompile"); !note.empty())
        std::cerr << note << "\n";
    }
    if (opt.emit == "flat") {
      text = model->print();
    } else {
      int status = 0;
      auto ode = lowered(*model, diags, opt, status, ctx);
      if (!ode) return status;
      if (opt.emit != "cpp") {
        text = mo::symbolic::print_ode(*ode);
      } else {
        try {
          return emit_cpp(*ode, diags, opt, ctx);
        } catch (const std::exception &e) {
          std::cerr << "mocompile: error: " << e.what() << "\n";
          return 1;
        }
      }
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
  app.add_option("file", opt.input,
                 "Modelica file (.mo, .mop, .opt) holding the class to compile, or an Xcos diagram "
                 "(.zcos, .xcos: compiled to flat Modelica by Scilab first)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("-c,--class", opt.class_name,
                 "Class to instantiate, as a dotted path (default: the last class in FILE)");
  app.add_option("-L,--library", opt.libs,
                 "Library file or directory of .mo files to load before FILE (repeatable)")
      ->check(CLI::ExistingPath);
  app.add_option("--emit", opt.emit,
                 "What to print: 'ast' (the parsed file), 'flat' (the flattened model), 'ode' (the "
                 "lowered model: states, ordered assignments and blocks, as flat Modelica), 'trace' "
                 "(each lowering stage, then the ode) or 'cpp' (C++ sources, into the directory -o DIR)")
      ->check(CLI::IsMember({"ast", "flat", "ode", "trace", "cpp"}))
      ->capture_default_str();
  app.add_option("-o,--output", opt.output, "Write the result to this file (atomically) instead of stdout");
  app.add_option("--cpp-name", opt.cpp_name,
                 "--emit cpp: C++ identifier used as namespace, file stem and factory prefix")
      ->check([](const std::string &s) {
        return mo::codegen::is_cpp_identifier(s) ? std::string() : "not a usable C++ identifier: " + s;
      })
      ->capture_default_str();
  app.add_option("--cpp-files", opt.cpp_files,
                 "--emit cpp: write exactly N <name>_part<K>.cpp files (for build systems)");
  app.add_option("--sensitivities", opt.sensitivities,
                 "Append forward sensitivity equations for these parameters (comma-separated); "
                 "implies --emit ode unless ode, trace or cpp is chosen")
      ->delimiter(',');
  app.add_flag("--no-balance-check", opt.no_balance_check,
               "Do not check that the model has as many equations as unknowns");
  app.add_flag("-q,--quiet", opt.quiet,
               "No progress on stderr (by default a stage longer than 2 s reports itself, at most once a second)");
  app.add_option("--max-errors", opt.max_errors, "Stop listing errors after this many")->capture_default_str();
  mo::tools::add_diagram_options(app, opt.diagram);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every command-line mistake exits 2.
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (!opt.sensitivities.empty() && (opt.emit == "flat" || opt.emit == "ast")) opt.emit = "ode";
  if (opt.emit == "cpp" && (opt.output.empty() || opt.output == "-")) {
    std::cerr << "mocompile: error: --emit cpp needs -o DIR\n";
    return 2;
  }
  mo::tools::Progress progress(std::cerr, mo::tools::stderr_progress_options(opt.quiet, "mocompile"));
  mo::tools::RunContext ctx;
  ctx.progress = &progress;
  std::unique_ptr<mo::tools::ExtractedDiagram> diagram;  // its temporary folder lives until the end
  try {
    if (mo::tools::is_diagram_file(opt.input)) {
      opt.diagram.quiet = true;  // the progress line shows the "diagram" stage
      std::vector<std::string> notes;
      {
        mo::tools::PhaseScope phase(&ctx, "diagram", opt.input);
        diagram = mo::tools::extract_flat_model(opt.input, opt.diagram);
        if (!opt.diagram.open_loop) notes = mo::tools::close_diagram_loop(*diagram, opt.diagram.tool);
      }
      for (const auto& line : notes) std::cerr << line << "\n";
      opt.input = diagram->flat_file().string();
      if (opt.diagram.init_fixed) opt.init_file = diagram->init_file().string();
      opt.from_diagram = true;
    }
    return run(opt, ctx);
  } catch (const mo::tools::DiagramError &e) {
    std::cerr << e.what() << "\n";
    return 1;
  } catch (const std::exception &e) {
    std::cerr << "mocompile: internal error: " << e.what() << "\n";
    return 3;
  }
}
