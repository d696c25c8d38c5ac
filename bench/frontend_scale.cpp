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

namespace {

/// N mass-spring-damper units in a chain, each unit a model with its own
/// connectors, connected by an array-indexed for-loop of connect equations.
std::string msd_chain(int n) {
  return R"(
package Bench
  connector Flange
    Real s;
    flow Real f;
  end Flange;
  model Mass
    parameter Real m = 1;
    Flange a, b;
    Real s(start = 0), v(start = 0);
  equation
    a.s = s; b.s = s;
    der(s) = v;
    m * der(v) = a.f + b.f;
  end Mass;
  model SpringDamper
    parameter Real c = 100, d = 1;
    Flange a, b;
    Real f;
  equation
    f = c * (b.s - a.s) + d * (der(b.s) - der(a.s));
    a.f = -f;
    b.f = f;
  end SpringDamper;
  model Unit
    Mass mass(m = 0.5);
    SpringDamper sd(c = 200);
    Flange a, b;
  equation
    connect(a, sd.a);
    connect(sd.b, mass.a);
    connect(mass.b, b);
  end Unit;
  model Fixed
    Flange a;
  equation
    a.s = 0;
  end Fixed;
  model Chain
    parameter Integer n = )" + std::to_string(n) + R"(;
    Fixed ground;
    Unit u[n];
  equation
    connect(ground.a, u[1].a);
    for i in 1:n - 1 loop
      connect(u[i].b, u[i + 1].a);
    end for;
  end Chain;
end Bench;
)";
}

/// An N-section RC ladder driven by a sine source.
std::string rc_ladder(int n) {
  return R"(
package Bench
  connector Pin
    Real v;
    flow Real i;
  end Pin;
  partial model TwoPin
    Pin p, n;
    Real v, i;
  equation
    v = p.v - n.v;
    0 = p.i + n.i;
    i = p.i;
  end TwoPin;
  model Resistor
    extends TwoPin;
    parameter Real R = 1;
  equation
    v = R * i;
  end Resistor;
  model Capacitor
    extends TwoPin;
    parameter Real C = 1;
  equation
    i = C * der(v);
  end Capacitor;
  model Ground
    Pin p;
  equation
    p.v = 0;
  end Ground;
  model Source
    extends TwoPin;
  equation
    v = sin(time);
  end Source;
  model Section
    Resistor r(R = 10);
    Capacitor c(C = 0.001);
    Pin a, b, g;
  equation
    connect(a, r.p);
    connect(r.n, b);
    connect(r.n, c.p);
    connect(c.n, g);
  end Section;
  model Ladder
    parameter Integer n = )" + std::to_string(n) + R"(;
    Source src;
    Ground gnd;
    Section s[n];
  equation
    connect(src.p, s[1].a);
    connect(src.n, gnd.p);
    for i in 1:n loop
      connect(s[i].g, gnd.p);
    end for;
    for i in 1:n - 1 loop
      connect(s[i].b, s[i + 1].a);
    end for;
  end Ladder;
end Bench;
)";
}

} // namespace

int main(int argc, char **argv) {
  if (argc != 3) {
    std::cerr << "usage: frontend_scale msd|rc N\n";
    return 2;
  }
  using namespace mo::frontend;
  std::string kind = argv[1];
  int n = std::stoi(argv[2]);
  std::string text = kind == "rc" ? rc_ladder(n) : msd_chain(n);
  std::string cls = kind == "rc" ? "Bench.Ladder" : "Bench.Chain";
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
