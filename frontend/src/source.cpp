#include "mo/frontend/source.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace mo::frontend {

FileId SourceManager::add(std::string name, std::string text) {
  auto f = std::make_unique<File>();
  f->name = std::move(name);
  f->text = std::move(text);
  f->line_starts.push_back(0);
  for (std::uint32_t i = 0; i < f->text.size(); ++i)
    if (f->text[i] == '\n')
      f->line_starts.push_back(i + 1);
  files_.push_back(std::move(f));
  return static_cast<FileId>(files_.size());
}

FileId SourceManager::load(const std::string &path, std::string &error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = "cannot open '" + path + "'";
    return 0;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) {
    error = "cannot read '" + path + "'";
    return 0;
  }
  std::string text = ss.str();
  if (text.size() >= UINT32_MAX) {
    error = "'" + path + "' is larger than 4 GiB";
    return 0;
  }
  return add(path, std::move(text));
}

const SourceManager::File &SourceManager::file(FileId id) const {
  if (id == 0 || id > files_.size())
    throw std::logic_error("internal error: bad FileId");
  return *files_[id - 1];
}

const std::string &SourceManager::name(FileId id) const { return file(id).name; }
std::string_view SourceManager::text(FileId id) const { return file(id).text; }

LineColumn SourceManager::position(FileId id, std::uint32_t offset) const {
  const File &f = file(id);
  auto it = std::upper_bound(f.line_starts.begin(), f.line_starts.end(), offset);
  std::uint32_t line = static_cast<std::uint32_t>(it - f.line_starts.begin());
  return {line, offset - f.line_starts[line - 1] + 1};
}

std::string_view SourceManager::line_text(FileId id, std::uint32_t offset) const {
  const File &f = file(id);
  LineColumn lc = position(id, offset);
  std::uint32_t begin = f.line_starts[lc.line - 1];
  std::uint32_t end = lc.line < f.line_starts.size() ? f.line_starts[lc.line] : f.text.size();
  while (end > begin && (f.text[end - 1] == '\n' || f.text[end - 1] == '\r'))
    --end;
  return std::string_view(f.text).substr(begin, end - begin);
}

} // namespace mo::frontend
