// Modelica's lookup rules in the file system: search roots, directory
// packages loaded lazily, `within`; and the mocompile CLI's roots (the
// directory of the compiled file, MODELICAPATH).
#include "compile.hpp"
#include "mo/frontend/flatten.hpp"
#include "mo/frontend/parser.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;
using namespace mo::test;
using namespace mo::frontend;

namespace {

/// A fresh directory under the system temp dir, removed at scope exit.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string &name) {
    path = fs::temp_directory_path() / ("mo_lookup_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  void write(const std::string &rel, const std::string &text) const {
    fs::create_directories((path / rel).parent_path());
    write_file((path / rel).string(), text);
  }
};

/// A library folder: one finished class, one that does not parse, a nested
/// package folder and a package.order.
void write_library(const TempDir &d) {
  d.write("Shelf/package.mo", "within;\npackage Shelf\n  constant Real gain = 3;\nend Shelf;\n");
  d.write("Shelf/package.order", "Decay\nDraft\nParts\n");
  d.write("Shelf/Decay.mo", "within Shelf;\nmodel Decay\n  parameter Real k = Shelf.Parts.rate;\n"
                            "  Real x(start = 1, fixed = true);\nequation\n  der(x) = -k * gain * x;\nend Decay;\n");
  d.write("Shelf/Draft.mo", "within Shelf;\nmodel Draft\n  Real y\nequation\n  der(y) = ;\nend Draft;\n");
  d.write("Shelf/Parts/package.mo", "within Shelf;\npackage Parts\n  constant Real rate = 0.5;\nend Parts;\n");
}

struct Loaded {
  std::unique_ptr<flat::Model> model;
  std::string diagnostics;
};

/// Compiles `main` (a file) with search roots, as mocompile does.
Loaded compile_with_roots(const std::string &main, const std::vector<std::string> &roots,
                          const std::vector<std::string> &package_dirs = {}) {
  SourceManager sources;
  DiagnosticEngine diags(sources);
  Library lib;
  lib.enable_loading(sources, diags);
  for (const auto &d : package_dirs)
    lib.add_package_directory(d);
  for (const auto &r : roots)
    lib.add_search_root(r);
  Loaded out;
  if (auto sd = parse_file(main, sources, diags)) {
    std::string cls = sd->classes.back()->name;
    lib.add(std::move(sd));
    out.model = flatten(lib, cls, diags);
  }
  std::ostringstream os;
  diags.print(os);
  out.diagnostics = os.str();
  return out;
}

int run(const std::string &cmd) {
  int status = std::system((cmd + " > /dev/null 2>&1").c_str());
  return WEXITSTATUS(status);
}

} // namespace

TEST_CASE("a library folder is found through a search root and loaded lazily", "[lookup]") {
  TempDir lib("root");
  write_library(lib);
  TempDir user("user");
  user.write("Use.mo", "model Use\n  Shelf.Decay d;\nend Use;\n");
  Loaded r = compile_with_roots((user.path / "Use.mo").string(), {(user.path).string(), lib.path.string()});
  INFO(r.diagnostics);
  REQUIRE(r.model);
  CHECK(r.diagnostics.empty()); // Shelf/Draft.mo was never parsed
  CHECK(r.model->variables[r.model->find("d.k")].value == 0.5);
  CHECK(r.model->print().find("der(`d.x`) = -`d.k` * 3. * `d.x`;") != std::string::npos);
}

TEST_CASE("a package directory given directly is loaded lazily too", "[lookup]") {
  TempDir lib("pkgdir");
  write_library(lib);
  TempDir user("user2");
  user.write("Use.mo", "model Use\n  Shelf.Decay d;\nend Use;\n");
  Loaded r = compile_with_roots((user.path / "Use.mo").string(), {}, {(lib.path / "Shelf").string()});
  INFO(r.diagnostics);
  CHECK(r.model);
}

TEST_CASE("using the unfinished class reports its syntax error", "[lookup]") {
  TempDir lib("draft");
  write_library(lib);
  TempDir user("user3");
  user.write("Use.mo", "model Use\n  Shelf.Draft d;\nend Use;\n");
  Loaded r = compile_with_roots((user.path / "Use.mo").string(), {lib.path.string()});
  CHECK_FALSE(r.model);
  CHECK(r.diagnostics.find("Draft.mo:4:1: error: unexpected 'equation'") != std::string::npos);
}

TEST_CASE("a class beside the compiled file is found - the first root wins", "[lookup]") {
  TempDir dir("beside");
  dir.write("Plant.mo", "model Plant\n  parameter Real a = 2;\n  Real x(start = 1, fixed = true);\n"
                        "equation\n  der(x) = -a * x;\nend Plant;\n");
  dir.write("Study.mo", "model Study\n  extends Plant(a = 4);\nend Study;\n");
  TempDir other("other");
  other.write("Plant.mo", "model Plant\n  parameter Real b = 1;\nend Plant;\n");
  Loaded r = compile_with_roots((dir.path / "Study.mo").string(), {dir.path.string(), other.path.string()});
  INFO(r.diagnostics);
  REQUIRE(r.model);
  CHECK(r.model->find("a") >= 0);
  CHECK(r.model->find("b") < 0);
}

TEST_CASE("mocompile looks beside the file and in MODELICAPATH", "[lookup][cli]") {
  TempDir lib("cli");
  write_library(lib);
  TempDir user("cliuser");
  user.write("Use.mo", "model Use\n  Shelf.Decay d;\nend Use;\n");
  const std::string mocompile = MO_MOCOMPILE;
  const std::string use = (user.path / "Use.mo").string();
  CHECK(run("env -u MODELICAPATH " + mocompile + " " + use) == 1); // Shelf unknown
  CHECK(run("MODELICAPATH=/nonexistent:" + lib.path.string() + " " + mocompile + " " + use) == 0);
  CHECK(run(mocompile + " " + use + " -L " + (lib.path / "Shelf").string()) == 0);
  user.write("Shelf.mo", "package Shelf\n  model Decay\n    Real x = 1;\n  end Decay;\nend Shelf;\n");
  CHECK(run("env -u MODELICAPATH " + mocompile + " " + use) == 0); // Shelf.mo beside the file
}
