#pragma once
/// Flattening: instantiate one class of a set of parsed files into a
/// flat::Model — name lookup through packages, extends and imports;
/// modifiers; array scalarisation; connect semantics; parameters evaluated.
#include "mo/frontend/ast.hpp"
#include "mo/frontend/diagnostics.hpp"
#include "mo/frontend/flat.hpp"

#include <memory>
#include <string>
#include <vector>

namespace mo::frontend {

struct FlattenOptions {
  /// Check that the model has as many equations as unknowns (Modelica's
  /// counting rules); an unbalanced model is an error naming likely culprits.
  bool check_balance = true;
  /// Deepest component nesting accepted (guards against recursive models).
  unsigned max_depth = 64;
  /// The most elements one array value may have (multiplications of one
  /// matrix product likewise), the most scalar variables a model may have,
  /// and the most times its for-equations may run in all; the loops of its
  /// algorithms and inlined functions may run 10 times that in all. A size
  /// one digit too long (`Real x[100000, 100000]`, `fill(0, 10^6, 10^6)`,
  /// `for i in 1:9000000`) is a diagnostic instead of hours and all memory.
  /// A million scalar variables take about 6 s and 2.3 GB to flatten.
  std::size_t max_elements = 1'000'000;
};

/// The classes of every file given to the compiler, as one package tree.
/// Files with `within P;` are placed inside package P.
class Library {
public:
  Library();
  ~Library();
  Library(const Library &) = delete;
  Library &operator=(const Library &) = delete;

  /// Adds a parsed file; the library keeps it.
  void add(std::unique_ptr<ast::StoredDefinition> file);
  /// The top-level class names, in the order they were added.
  std::vector<std::string> top_level_names() const;

  /// Lets lookup load classes from the file system (Modelica 3.x 13.2.4):
  /// files are parsed into `sources` when a lookup first reaches them, and
  /// their errors go to `diags` (both must outlive the library).
  void enable_loading(SourceManager &sources, DiagnosticEngine &diags);
  /// Adds a root searched, in the order added, for a top-level class `Name`
  /// not among the added files: `root/Name.mo`, then `root/Name/package.mo`.
  void add_search_root(const std::string &directory);
  /// Adds the package stored in `directory` (a `package.mo` beside one file
  /// or folder per class); its classes are parsed when lookup reaches them.
  /// False, with nothing added, when `directory/package.mo` cannot be parsed.
  bool add_package_directory(const std::string &directory);

  struct Impl;
  Impl &impl() { return *impl_; }

private:
  std::unique_ptr<Impl> impl_;
};

/// Flattens class `class_name` (a dotted path) of `lib`. Reports every
/// problem to `diags`; returns null when there were errors.
std::unique_ptr<flat::Model> flatten(Library &lib, const std::string &class_name,
                                     DiagnosticEngine &diags, const FlattenOptions &options = {});

} // namespace mo::frontend
