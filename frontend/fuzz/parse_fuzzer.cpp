// libFuzzer target: any bytes through the parser and, when they parse,
// through flattening. Nothing may crash, hang or trip a sanitizer.
#include "mo/frontend/flatten.hpp"
#include "mo/frontend/parser.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size) {
  using namespace mo::frontend;
  SourceManager sources;
  DiagnosticEngine diags(sources);
  FileId id = sources.add("fuzz.mo", std::string(reinterpret_cast<const char *>(data), size));
  auto sd = parse(id, sources, diags);
  if (!sd || sd->classes.empty())
    return 0;
  std::string name = sd->classes.back()->name;
  Library lib;
  lib.add(std::move(sd));
  (void)flatten(lib, name, diags);
  std::string out;
  for (const auto &d : diags.all())
    out += diags.format(d);
  return 0;
}
