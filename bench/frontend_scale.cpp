// Front-end scale benchmark: parse + flatten a generated hierarchical chain
// of N units. Prints one line: kind N flat_equations parse_s flatten_s peak_rss_MB.
// Usage: frontend_scale msd|rc N   (run each N in its own process: peak RSS)
#include "mo/frontend/flatten.hpp"
#include "mo/frontend/parser.hpp"

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>

#include "chains.hpp"



int main(int argc, char **argv) {
  if (argc != 3) {
    std::cerr << "usage: frontend_scale msd|rc N\n";
    return 2;
  }
  using namespace mo::frontend;
  std::string kind = argv[1];
  int n = std::stoi(argv[2]);
  auto [text, cls] = mo::bench::chain_model(kind, n);
  using clock = std::chrono::steady_clock;
  auto t0 = clock::now();
  SourceManager sources;
  DiagnosticEngine diags(sources);
  auto sd = parse(sources.add("bench.mo", text), sources, diags);
  auto t1 = clock::now();
  if (!sd) {
    diags.print(std::cerr);
    return 1;
  }
  Library lib;
  lib.add(std::move(sd));
  auto model = flatten(lib, cls, diags);
  auto t2 = clock::now();
  if (!model) {
    diags.print(std::cerr);
    return 1;
  }
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  std::printf("%s %d %zu %.3f %.3f %.1f\n", kind.c_str(), n, model->equations.size(),
              std::chrono::duration<double>(t1 - t0).count(), std::chrono::duration<double>(t2 - t1).count(),
              ru.ru_maxrss / 1024.0);
  return 0;
}
