#pragma once
/// Parsing: Modelica / Optimica / Xcos flat text → ast::StoredDefinition.
#include "mo/frontend/ast.hpp"
#include "mo/frontend/diagnostics.hpp"

#include <memory>

namespace mo::frontend {

struct ParseOptions {
  /// Deepest expression tree accepted: brackets, if-expressions and chained
  /// binary operators (`a - b - c` is two levels) of one statement; deeper
  /// input gets a diagnostic instead of exhausting a later stage's stack.
  unsigned max_nesting = 1000;
};

/// Parses the file `file` of `sources`. Every lexical and syntax error is
/// reported to `diags`; on any error the result is null (no partial AST).
std::unique_ptr<ast::StoredDefinition> parse(FileId file, const SourceManager &sources,
                                             DiagnosticEngine &diags,
                                             const ParseOptions &options = {});

/// Convenience: loads `path` into `sources` and parses it. Reports a
/// cannot-read-file diagnostic and returns null when the file cannot be read.
std::unique_ptr<ast::StoredDefinition> parse_file(const std::string &path, SourceManager &sources,
                                                  DiagnosticEngine &diags,
                                                  const ParseOptions &options = {});

} // namespace mo::frontend
