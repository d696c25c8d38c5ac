#include "compile.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace mo::test {

using namespace frontend;

Compiled compile(const std::vector<Source> &sources, std::string class_name, bool check_balance) {
  FlattenOptions fo;
  fo.check_balance = check_balance;
  return compile(sources, std::move(class_name), fo);
}

Compiled compile(const std::vector<Source> &sources, std::string class_name, const FlattenOptions &fo) {
  SourceManager sm;
  DiagnosticEngine diags(sm);
  Library lib;
  Compiled out;
  bool parsed = true;
  for (const auto &s : sources) {
    FileId id = sm.add(s.name, s.text);
    auto sd = parse(id, sm, diags);
    if (!sd) {
      parsed = false;
      continue;
    }
    if (&s == &sources.back() && class_name.empty() && !sd->classes.empty())
      class_name = sd->classes.back()->name;
    lib.add(std::move(sd));
  }
  if (parsed)
    out.model = flatten(lib, class_name, diags, fo);
  std::ostringstream os;
  diags.print(os);
  out.diagnostics = os.str();
  return out;
}

Compiled compile_text(const std::string &text, std::string class_name) {
  return compile({{"test.mo", text}}, std::move(class_name));
}

std::vector<ManifestRow> scilab_manifest() {
  std::ifstream in(std::string(MO_TEST_DATA_DIR) + "/scilab/MANIFEST");
  std::vector<ManifestRow> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    ManifestRow r;
    ls >> r.file >> r.library >> r.cls >> r.instance >> r.unknowns >> r.equations >> r.parameters;
    rows.push_back(r);
  }
  return rows;
}

std::string read_file(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_file(const std::string &path, const std::string &text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::vector<std::string> list_files(const std::string &dir, const std::string &suffix) {
  std::vector<std::string> out;
  for (auto &e : std::filesystem::directory_iterator(dir)) {
    std::string p = e.path().string();
    if (p.size() >= suffix.size() && p.compare(p.size() - suffix.size(), suffix.size(), suffix) == 0)
      out.push_back(p);
  }
  std::sort(out.begin(), out.end());
  return out;
}

} // namespace mo::test
