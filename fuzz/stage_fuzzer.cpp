// libFuzzer targets, one per pipeline stage (MO_FUZZ_STAGE selects it):
//
//   1 parse     bytes → AST
//   2 flatten   bytes → AST → flat::Model          (MoLib loaded when named)
//   3 lower     ... → OdeModel (print_ode too)
//   4 cpp       ... → generated C++ text (not compiled)
//
// Any input must end in diagnostics or a result: nothing may crash, hang,
// throw out of a stage, or trip a sanitizer. Seeds: every model of the
// repository (scripts/fuzz.sh).
#include "mo/codegen/generate.hpp"
#include "mo/frontend/flatten.hpp"
#include "mo/frontend/parser.hpp"
#include "mo/symbolic/lower.hpp"
#include "mo/symbolic/ode.hpp"

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>

#ifndef MO_FUZZ_STAGE
#error "MO_FUZZ_STAGE must be 1 (parse), 2 (flatten), 3 (lower) or 4 (cpp)"
#endif

namespace {

using namespace mo;

/// The text of MoLib (MO_FUZZ_LIBRARY), read once; empty if unreadable.
const std::string &library_text() {
  static const std::string text = [] {
    std::ifstream in(MO_FUZZ_LIBRARY);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }();
  return text;
}

void run(const std::string &text) {
  frontend::SourceManager sources;
  frontend::DiagnosticEngine diags(sources);
  const frontend::FileId id = sources.add("fuzz.mo", text);
  auto sd = frontend::parse(id, sources, diags);
  for (const auto &d : diags.all()) (void)diags.format(d);
  if (MO_FUZZ_STAGE < 2 || !sd || sd->classes.empty()) return;
  const std::string name = sd->classes.back()->name;
  frontend::Library lib;
  // MoLib only for inputs that name it: parsing it costs more than most
  // inputs, and every execution would pay for it.
  if (text.find("MoLib") != std::string::npos && !library_text().empty()) {
    frontend::DiagnosticEngine lib_diags(sources);
    if (auto molib = frontend::parse(sources.add("MoLib.mo", library_text()), sources, lib_diags))
      lib.add(std::move(molib));
  }
  lib.add(std::move(sd));
  // Inputs look for crashes and hangs, not for the largest model a user may
  // flatten (bench/frontend_scale measures that): a size that a mutation
  // made a million would only measure the time a million scalars take.
  frontend::FlattenOptions options;
  options.max_elements = 10'000;
  auto flat = frontend::flatten(lib, name, diags, options);
  for (const auto &d : diags.all()) (void)diags.format(d);
  if (MO_FUZZ_STAGE < 3 || !flat) return;
  auto ode = symbolic::lower(*flat, diags);
  for (const auto &d : diags.all()) (void)diags.format(d);
  if (!ode) return;
  (void)symbolic::print_ode(*ode);
  if (MO_FUZZ_STAGE < 4) return;
  (void)codegen::generate_cpp(*ode);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size) {
  run(std::string(reinterpret_cast<const char *>(data), size));
  return 0;
}
