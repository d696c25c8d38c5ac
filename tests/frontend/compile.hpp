#pragma once
// Test helpers: parse and flatten text or files, capturing diagnostics.
#include "mo/frontend/flatten.hpp"
#include "mo/frontend/parser.hpp"

#include <memory>
#include <string>
#include <vector>

namespace mo::test {

struct Compiled {
  std::unique_ptr<frontend::flat::Model> model;
  std::string diagnostics; ///< everything printed, clang style
  bool ok() const { return model != nullptr; }
};

/// One source: a display name and its text.
struct Source {
  std::string name;
  std::string text;
};

/// Parses every source (libraries first, the model last) and flattens
/// `class_name` (default: the last class of the last source).
Compiled compile(const std::vector<Source> &sources, std::string class_name = "",
                 bool check_balance = true);
Compiled compile(const std::vector<Source> &sources, std::string class_name,
                 const frontend::FlattenOptions &options);
Compiled compile_text(const std::string &text, std::string class_name = "");

/// One row of tests/frontend/data/scilab/MANIFEST: a hierarchical model
/// built from a Scilab library, with the counts of modelicat's flat output.
struct ManifestRow {
  std::string file, library, cls, instance;
  int unknowns = 0, equations = 0, parameters = 0;
};
std::vector<ManifestRow> scilab_manifest();

std::string read_file(const std::string &path);
void write_file(const std::string &path, const std::string &text);
std::vector<std::string> list_files(const std::string &dir, const std::string &suffix);

} // namespace mo::test
