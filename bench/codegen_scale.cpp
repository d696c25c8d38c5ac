// Code generation benchmark: generate + compile (c++ -O1) the cart pendulum
// and a chain of N mass-spring-damper units (hand-lowered, as the lowering is
// not in this build yet), then the cached rerun. Prints one line per model:
//   model N states instructions files generate_s compile_s cached_s
// Usage: codegen_scale [N ...]   (default: 100 1000 10000); jobs from MO_JOBS (default 2)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "codegen/models.hpp"
#include "mo/codegen/generate.hpp"
#include "mo/codegen/shared_object.hpp"

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void measure(const std::string& label, int n, mo::symbolic::OdeModel (*build)(int)) {
  mo::symbolic::OdeModel model = build(n);
  using namespace mo::codegen;
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t states = model.states.size();
  const GeneratedSources src = generate_cpp(model);
  const double generate_s = seconds_since(t0);
  if (const char* keep = std::getenv("MO_BENCH_SOURCES"))  // for inspecting the generated code
    write_sources(src, std::string(keep) + "/" + label + std::to_string(n));
  CompilerOptions o = runtime_compiler_options();
  o.cache_dir = (std::filesystem::temp_directory_path() / "mocompile-bench-cache").string();
  const char* jobs = std::getenv("MO_JOBS");
  o.jobs = jobs ? static_cast<unsigned>(std::atoi(jobs)) : 2u;
  std::filesystem::remove_all(o.cache_dir);
  const CompiledModel first = compile_shared_object(src, o);
  const auto t1 = std::chrono::steady_clock::now();
  const CompiledModel second = compile_shared_object(generate_cpp(*std::make_unique<mo::symbolic::OdeModel>(build(n))), o);
  const double cached_s = seconds_since(t1);
  auto instance = LoadedModel(second.library, src.factory_symbol).create();
  std::printf("%s %d %zu %zu %zu %.3f %.2f %.3f%s\n", label.c_str(), n, states, src.instructions,
              src.sources().size(), generate_s, first.seconds, cached_s,
              second.cached && instance->info().states.size() == states ? "" : " (cache miss!)");
  std::filesystem::remove_all(o.cache_dir);
}

}  // namespace

int main(int argc, char** argv) {
  std::printf("model N states instructions files generate_s compile_s cached_rerun_s\n");
  measure("cart_pendulum", 1, [](int) { return mo::codegen::test::cart_pendulum(); });
  for (int i = 1; i < argc || argc == 1; ++i) {
    if (argc == 1) {
      for (int n : {100, 1000, 10000}) measure("msd_chain", n, mo::codegen::test::spring_chain);
      break;
    }
    const int n = std::atoi(argv[i]);
    measure("msd_chain", n, mo::codegen::test::spring_chain);
  }
}
