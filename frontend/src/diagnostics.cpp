#include "mo/frontend/diagnostics.hpp"

#include <ostream>

namespace mo::frontend {

namespace {
struct DiagInfo {
  Severity severity;
  const char *name;
};
constexpr DiagInfo kDiagTable[] = {
#define MO_DIAG(id, severity, name) {Severity::severity, name},
#include "mo/frontend/diagnostic_kinds.def"
#undef MO_DIAG
};

const char *severity_text(Severity s) {
  switch (s) {
  case Severity::Note: return "note";
  case Severity::Warning: return "warning";
  case Severity::Error: return "error";
  }
  return "?";
}

/// Printable form of a source line: tabs kept (so the caret lines up),
/// control and non-ASCII bytes shown as '?', very long lines cut around the
/// column of interest.
std::string printable(std::string_view line) {
  std::string out;
  out.reserve(line.size());
  for (unsigned char c : line)
    out += (c == '\t' || (c >= 0x20 && c < 0x7f)) ? static_cast<char>(c) : '?';
  return out;
}
} // namespace

const char *diag_name(DiagId id) { return kDiagTable[static_cast<int>(id)].name; }
Severity diag_severity(DiagId id) { return kDiagTable[static_cast<int>(id)].severity; }

Diagnostic &DiagnosticEngine::report(DiagId id, SourceRange range, std::string message) {
  Severity s = diag_severity(id);
  // Parser error recovery can report the same mistake twice in a row.
  if (!diags_.empty() && diags_.back().id == id && diags_.back().range.file == range.file &&
      diags_.back().range.begin == range.begin && diags_.back().message == message)
    return diags_.back();
  if (s == Severity::Error) {
    ++error_count_;
    if (error_count_ > max_errors_) {
      truncated_ = true;
      dropped_ = Diagnostic{id, s, range, std::move(message), {}};
      return dropped_;
    }
  }
  diags_.push_back(Diagnostic{id, s, range, std::move(message), {}});
  return diags_.back();
}

void DiagnosticEngine::note(SourceRange range, std::string message) {
  if (!diags_.empty() && !truncated_)
    diags_.back().notes.push_back(Note{range, std::move(message)});
}

std::string DiagnosticEngine::format_one(Severity s, SourceRange r, const std::string &msg) const {
  std::string out;
  if (!r.valid()) {
    out = std::string("mocompile: ") + severity_text(s) + ": " + msg + "\n";
    return out;
  }
  LineColumn lc = sources_.position(r.file, r.begin);
  out = sources_.name(r.file) + ":" + std::to_string(lc.line) + ":" + std::to_string(lc.column) +
        ": " + severity_text(s) + ": " + msg + "\n";
  std::string line = printable(sources_.line_text(r.file, r.begin));
  std::size_t col = lc.column - 1;
  std::size_t start = 0;
  constexpr std::size_t kWidth = 160;
  if (line.size() > kWidth) { // show a window of the line around the column
    start = col > kWidth / 2 ? col - kWidth / 2 : 0;
    line = (start > 0 ? "..." : "") + line.substr(start, kWidth) + "...";
    if (start > 0)
      col = col - start + 3;
  }
  out += line + "\n";
  std::string caret;
  const std::string_view src = sources_.line_text(r.file, r.begin);
  for (std::size_t i = 0; i < col; ++i) {
    std::size_t srci = start + i - (start > 0 ? 3 : 0);
    caret += (i < line.size() && srci < src.size() && src[srci] == '\t') ? '\t' : ' ';
  }
  std::size_t len = r.end > r.begin ? r.end - r.begin : 1;
  std::size_t line_rest = line.size() > col ? line.size() - col : 1;
  caret += '^';
  for (std::size_t i = 1; i < len && i < line_rest && i < 80; ++i)
    caret += '~';
  out += caret + "\n";
  return out;
}

std::string DiagnosticEngine::format(const Diagnostic &d) const {
  std::string out = format_one(d.severity, d.range, d.message);
  for (const Note &n : d.notes)
    out += format_one(Severity::Note, n.range, n.message);
  return out;
}

void DiagnosticEngine::print(std::ostream &os) const {
  for (const Diagnostic &d : diags_)
    os << format(d);
  if (truncated_)
    os << "mocompile: note: " << (error_count_ - max_errors_)
       << " more errors not shown\n";
}

} // namespace mo::frontend
