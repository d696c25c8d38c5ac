#pragma once
/// Source text and positions. A SourceRange is a byte range in one file;
/// line and column are computed only when a diagnostic is printed.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace mo::frontend {

/// Index of a file in a SourceManager; 0 means "no file" (generated text).
using FileId = std::uint32_t;

/// A half-open byte range [begin, end) in one file.
struct SourceRange {
  FileId file = 0;
  std::uint32_t begin = 0;
  std::uint32_t end = 0;
  /// True when the range points into a real file.
  bool valid() const { return file != 0; }
};

/// 1-based line and column of a byte offset.
struct LineColumn {
  std::uint32_t line = 0;
  std::uint32_t column = 0;
};

/// Owns the text of every file read during a compilation.
class SourceManager {
public:
  /// Adds a file's text under `name`; returns its id (never 0).
  FileId add(std::string name, std::string text);
  /// Reads `path` from disk; returns 0 and sets `error` when it cannot.
  FileId load(const std::string &path, std::string &error);

  const std::string &name(FileId id) const;
  std::string_view text(FileId id) const;
  /// Line and column of `offset` in `id` (1-based; the column counts bytes).
  LineColumn position(FileId id, std::uint32_t offset) const;
  /// The whole line holding `offset`, without its line terminator.
  std::string_view line_text(FileId id, std::uint32_t offset) const;

private:
  struct File {
    std::string name;
    std::string text;
    std::vector<std::uint32_t> line_starts;
  };
  std::vector<std::unique_ptr<File>> files_;
  const File &file(FileId id) const;
};

} // namespace mo::frontend
