// Expandable connectors (MLS 9.1.3): elements present only where connected,
// undeclared elements added with the other side's type, connected buses
// sharing their elements, nested buses. The simulation of BusLoop against
// its closed form is in tests/e2e/test_circuits.cpp.
#include "compile.hpp"

#include <catch2/catch.hpp>

using namespace mo::test;

namespace {

/// tests/e2e/data/BusLoop.mo: buses, a sub-bus, an undeclared element, and
/// declared elements that nothing connects.
Compiled bus_loop(const std::string &cls, const std::string &extra = "") {
  const std::string text = read_file(std::string(MO_SOURCE_DIR) + "/tests/e2e/data/BusLoop.mo");
  std::vector<Source> sources{{"BusLoop.mo", text}};
  if (!extra.empty())
    sources.push_back({"Extra.mo", extra});
  return compile(sources, cls);
}

} // namespace

TEST_CASE("expandable connectors: elements exist where connected, buses share them", "[flatten][expandable]") {
  Compiled c = bus_loop("BusLoop.Loop");
  INFO(c.diagnostics);
  REQUIRE(c.ok()); // balanced: each present element is one unknown, one equation
  const std::string s = c.model->print();
  INFO(s);
  // Declared and connected, through the sub-bus pair (plant.sub, bus.sub)
  // and the bus pair (ctrl.bus, bus): present on every bus of the set.
  for (const char *v : {"plant.sub.speed", "bus.sub.speed", "ctrl.bus.sub.speed"})
    CHECK(c.model->find(v) >= 0);
  // Undeclared, added with the type of `ctrl.u` and propagated to `bus`.
  for (const char *v : {"ctrl.bus.command", "bus.command"})
    CHECK(c.model->find(v) >= 0);
  CHECK(s.find("  Real `bus.command`;") != std::string::npos); // neither input nor output
  // Declared but connected nowhere: not in the flat model.
  for (const char *v : {"plant.sub.spare", "bus.sub.spare", "bus.enabled", "ctrl.bus.enabled"})
    CHECK(c.model->find(v) < 0);
  CHECK(s.find("`ctrl.u` = `ctrl.bus.command`;") != std::string::npos);
  CHECK(s.find("`ctrl.e` = 1 - `ctrl.bus.sub.speed`;") != std::string::npos);
}

TEST_CASE("expandable connectors: a modifier may name a declared element", "[flatten][expandable]") {
  Compiled c = bus_loop("Started", R"(
model Started
  extends BusLoop.Loop(bus(sub(speed(start = 0.5))));
end Started;
)");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  CHECK(c.model->print().find("`bus.sub.speed`(start = 0.5)") != std::string::npos);
}

TEST_CASE("expandable connectors: two undeclared elements cannot be connected", "[flatten][expandable]") {
  const char *src = R"(
expandable connector Bus
end Bus;
model M
  Bus a, b;
equation
  connect(a.x, b.y);
end M;
)";
  Compiled c = compile_text(src, "M");
  CHECK_FALSE(c.ok());
  CHECK(c.diagnostics.find("7:3: error: connect() of two undeclared elements 'a.x' and 'b.y'") !=
        std::string::npos);
}

TEST_CASE("expandable connectors: an array connected to an undeclared element", "[flatten][expandable]") {
  const char *src = R"(
connector RealOutput = output Real;
connector RealInput = input Real;
expandable connector Bus
end Bus;
model Sensors
  RealOutput y[3];
  Bus bus;
equation
  y = {time, 2 * time, 3 * time};
  connect(y, bus.v);
end Sensors;
model Sum
  RealInput u[3];
  Bus bus;
  Real total = sum(u);
equation
  connect(bus.v, u);
end Sum;
model Rig
  Sensors s;
  Sum a;
  Bus bus;
equation
  connect(s.bus, bus);
  connect(a.bus, bus);
end Rig;
)";
  Compiled c = compile_text(src, "Rig");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string s = c.model->print();
  INFO(s);
  for (const char *v : {"bus.v[1]", "bus.v[3]", "s.bus.v[2]", "a.bus.v[3]"})
    CHECK(c.model->find(v) >= 0);
  CHECK(c.model->find("bus.v[4]") < 0);
}
