#pragma once
/// Diagnostics: every user-facing error, warning and note of the front end
/// (and of later stages that point at model text). They are collected, not
/// thrown, and printed as `file.mo:12:5: error: message` with the source line
/// and a caret. Every kind is listed once in diagnostic_kinds.def.
#include "mo/frontend/source.hpp"

#include <iosfwd>
#include <string>
#include <vector>

namespace mo::frontend {

enum class Severity { Note, Warning, Error };

/// Identifies a diagnostic kind; the table in diagnostic_kinds.def gives each
/// its severity and a stable name (shown with --diagnostic-ids).
enum class DiagId {
#define MO_DIAG(id, severity, name) id,
#include "mo/frontend/diagnostic_kinds.def"
#undef MO_DIAG
};

/// The stable, human-readable name of a diagnostic kind (e.g. "unknown-class").
const char *diag_name(DiagId id);
Severity diag_severity(DiagId id);

struct Note {
  SourceRange range;
  std::string message;
};

struct Diagnostic {
  DiagId id;
  Severity severity;
  SourceRange range;
  std::string message;
  std::vector<Note> notes;
};

/// Collects diagnostics. Stops recording (but keeps counting) after
/// `max_errors` errors so binary garbage cannot flood the output.
class DiagnosticEngine {
public:
  explicit DiagnosticEngine(const SourceManager &sources, unsigned max_errors = 50)
      : sources_(sources), max_errors_(max_errors) {}

  /// Records a diagnostic; returns it so that notes can be added.
  Diagnostic &report(DiagId id, SourceRange range, std::string message);
  /// Adds a note to the last recorded diagnostic (ignored if none).
  void note(SourceRange range, std::string message);

  bool has_errors() const { return error_count_ > 0; }
  unsigned error_count() const { return error_count_; }
  const std::vector<Diagnostic> &all() const { return diags_; }
  /// The files the diagnostics' ranges point into.
  const SourceManager &sources() const { return sources_; }

  /// What has been reported so far, to roll back to.
  struct Mark {
    std::size_t size;
    unsigned errors;
    bool truncated;
  };
  Mark mark() const { return {diags_.size(), error_count_, truncated_}; }
  /// Forgets what was reported since `m`: a look ahead whose findings are
  /// reported again where they belong.
  void rollback(const Mark &m) {
    diags_.resize(m.size);
    error_count_ = m.errors;
    truncated_ = m.truncated;
  }

  /// Prints every diagnostic in the order reported, clang style.
  void print(std::ostream &os) const;
  /// One diagnostic as text (used by print and by tests).
  std::string format(const Diagnostic &d) const;

private:
  const SourceManager &sources_;
  unsigned max_errors_;
  unsigned error_count_ = 0;
  bool truncated_ = false;
  Diagnostic dropped_{};
  std::vector<Diagnostic> diags_;
  std::string format_one(Severity s, SourceRange r, const std::string &msg) const;
};

} // namespace mo::frontend
