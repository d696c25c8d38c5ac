// Generated hierarchical test models of any size, shared by the benchmarks:
// a chain of N mass-spring-damper units and an N-section RC ladder.
#pragma once

#include <string>

namespace mo::bench {


/// N mass-spring-damper units in a chain, each unit a model with its own
/// connectors, connected by an array-indexed for-loop of connect equations.
inline std::string msd_chain(int n) {
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
inline std::string rc_ladder(int n) {
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


/// The model text and the class to flatten for `kind` ("msd" or "rc").
inline std::pair<std::string, std::string> chain_model(const std::string& kind, int n) {
  if (kind == "rc") return {rc_ladder(n), "Bench.Ladder"};
  return {msd_chain(n), "Bench.Chain"};
}

}  // namespace mo::bench
