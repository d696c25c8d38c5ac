// Classes loaded from the file system by Modelica's lookup rules (Modelica
// 3.x 13.2.4): a top-level class `Name` not among the given files is
// `root/Name.mo` or `root/Name/package.mo` in the first search root that has
// it; a class of a package stored as a directory is `dir/Name.mo` or
// `dir/Name/package.mo`. Files are parsed only when a lookup reaches them, so
// an unfinished class of a library never fails a model that does not use it.
#include "flattener.hpp"
#include "mo/frontend/parser.hpp"

#include <filesystem>

namespace fs = std::filesystem;

namespace mo::frontend {

namespace {

/// True for a name that can be a file name in a search (no path syntax).
bool loadable_name(const std::string &name) {
  if (name.empty() || name == "." || name == "..")
    return false;
  for (char c : name)
    if (c == '/' || c == '\\' || c == '\0' || c == '\'' || c == '`')
      return false;
  return true;
}

bool is_file(const fs::path &p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

} // namespace

void Library::enable_loading(SourceManager &sources, DiagnosticEngine &diags) {
  impl_->sources = &sources;
  impl_->diags = &diags;
}

void Library::add_search_root(const std::string &directory) { impl_->roots.push_back(directory); }

bool Library::add_package_directory(const std::string &directory) {
  fs::path dir = fs::path(directory).lexically_normal();
  if (dir.filename().empty())
    dir = dir.parent_path(); // "Lib/" names the folder Lib
  const std::string name = dir.filename().string();
  if (!impl_->sources || !loadable_name(name) || !is_file(dir / "package.mo"))
    return false;
  impl_->tried.insert({&impl_->root, name});
  if (!impl_->load_file(impl_->root, (dir / "package.mo").string()))
    return false;
  auto it = impl_->root.children.find(name);
  if (it == impl_->root.children.end())
    return false;
  impl_->directory_of[it->second.get()] = dir.string();
  return true;
}

bool Library::Impl::load_file(ClassNode &parent, const std::string &file) {
  auto sd = parse_file(file, *sources, *diags);
  if (!sd)
    return false;
  // The file's place is where lookup found it; its `within` only restates it.
  for (const auto &cls : sd->classes) {
    if (&parent == &root && !parent.children.count(cls->name))
      order.push_back(cls->name);
    insert(parent, *cls);
  }
  files.push_back(std::move(sd));
  return true;
}

ClassNode *Library::Impl::load_member(ClassNode &parent, const std::string &name) {
  if (!sources || !loadable_name(name) || !tried.insert({&parent, name}).second)
    return nullptr;
  std::vector<std::string> dirs;
  if (&parent == &root) {
    dirs = roots;
  } else if (auto it = directory_of.find(&parent); it != directory_of.end()) {
    dirs.push_back(it->second);
  }
  auto defined = [&]() -> ClassNode * {
    auto it = parent.children.find(name);
    return it != parent.children.end() && it->second->def ? it->second.get() : nullptr;
  };
  for (const std::string &dir : dirs) {
    const fs::path file = fs::path(dir) / (name + ".mo");
    if (is_file(file)) {
      load_file(parent, file.string());
      return defined();
    }
    const fs::path package = fs::path(dir) / name / "package.mo";
    if (is_file(package)) {
      load_file(parent, package.string());
      ClassNode *node = defined();
      if (node)
        directory_of[node] = (fs::path(dir) / name).string();
      return node;
    }
  }
  return nullptr;
}

} // namespace mo::frontend
