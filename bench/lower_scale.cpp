// Lowering scale benchmark: flatten + lower a generated chain of N units, then
// optionally append sensitivities for the first K parameters.
// Prints one line: kind N K flat_equations states flatten_s lower_s sens_s peak_rss_MB.
// Usage: lower_scale msd|rc N [K]   (run each case in its own process: peak RSS)
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <numeric>
#include <string>

#include "chains.hpp"
#include "mo/frontend/flatten.hpp"
#include "mo/frontend/parser.hpp"
#include "mo/symbolic/lower.hpp"
#include "mo/symbolic/sensitivities.hpp"

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::cerr << "usage: lower_scale msd|rc N [K]\n";
    return 2;
  }
  using namespace mo::frontend;
  using clock = std::chrono::steady_clock;
  const std::string kind = argv[1];
  const int n = std::stoi(argv[2]);
  const std::size_t k = argc == 4 ? std::stoul(argv[3]) : 0;
  auto [text, cls] = mo::bench::chain_model(kind, n);
  const auto t0 = clock::now();
  SourceManager sources;
  DiagnosticEngine diags(sources);
  auto sd = parse(sources.add("bench.mo", text), sources, diags);
  if (!sd) return diags.print(std::cerr), 1;
  Library lib;
  lib.add(std::move(sd));
  auto flat = flatten(lib, cls, diags);
  if (!flat) return diags.print(std::cerr), 1;
  const auto t1 = clock::now();
  auto ode = mo::symbolic::lower(*flat, diags);
  if (!ode) return diags.print(std::cerr), 1;
  const auto t2 = clock::now();
  std::vector<std::size_t> params(std::min(k, ode->parameters.size()));
  std::iota(params.begin(), params.end(), std::size_t{0});
  if (!params.empty()) mo::symbolic::add_sensitivities(*ode, params);
  const auto t3 = clock::now();
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  auto s = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  std::printf("%s %d %zu %zu %zu %.3f %.3f %.3f %.1f\n", kind.c_str(), n, params.size(),
              flat->equations.size(), ode->states.size(), s(t0, t1), s(t1, t2), s(t2, t3),
              ru.ru_maxrss / 1024.0);
  return 0;
}
