// Redeclarations and replaceable elements (MLS 7.3) and inner/outer
// elements (MLS 5.4): each model in data/elements/ flattens to the exact flat text pinned beside it
// (NAME.mo → NAME.flat; MO_UPDATE_GOLDEN=1 rewrites them), and that text
// flattens again to itself. Bad redeclarations are pinned in data/bad/.
#include "compile.hpp"

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>

using namespace mo::test;

namespace {
const std::string kElements = std::string(MO_TEST_DATA_DIR) + "/elements/";

std::string flat_of(const std::string &name, const std::string &text) {
  Compiled c = compile({{name, text}});
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  CHECK(c.diagnostics.empty());
  return c.model->print();
}

std::string errors_of(const std::string &text) {
  Compiled c = compile({{"m.mo", text}});
  CHECK_FALSE(c.ok());
  return c.diagnostics;
}

bool contains(const std::string &s, const std::string &part) { return s.find(part) != std::string::npos; }
} // namespace

TEST_CASE("every element-prefix model flattens to its pinned flat text, which flattens to itself", "[redeclare]") {
  auto files = list_files(kElements, ".mo");
  REQUIRE(files.size() >= 4);
  const bool update = std::getenv("MO_UPDATE_GOLDEN") != nullptr;
  for (const auto &f : files) {
    INFO("model: " << f);
    const std::string name = std::filesystem::path(f).filename().string();
    const std::string got = flat_of(name, read_file(f));
    const std::string expected_path = f.substr(0, f.size() - 3) + ".flat";
    if (update)
      write_file(expected_path, got);
    CHECK(got == read_file(expected_path));
    CHECK(flat_of(name + ".flat", got) == got);
  }
}

TEST_CASE("the outermost redeclaration wins, and a redeclared array element type applies to every element",
          "[redeclare]") {
  const std::string s = flat_of("m.mo", R"(
    model M
      block A
        parameter Real k = 1;
        output Real y = k;
      end A;
      block B
        parameter Real k = 1;
        output Real y = 2 * k;
      end B;
      block C
        parameter Real k = 1;
        output Real y = 3 * k;
      end C;
      model H
        replaceable A a[2];
      end H;
      model H2
        extends H(redeclare B a[2]);
      end H2;
      H2 h(redeclare C a[2](each k = 4));
    end M;)");
  CHECK(contains(s, "`h.a[1].y` = 3 * `h.a[1].k`;"));
  CHECK(contains(s, "`h.a[2].k` = 4;"));
}

TEST_CASE("bad redeclarations are reported at the redeclaration", "[redeclare]") {
  SECTION("a final replaceable element") {
    const std::string d = errors_of(R"(
      model M
        block A output Real y = 1; end A;
        block B output Real y = 2; end B;
        model H final replaceable A a; end H;
        H h(redeclare B a);
      end M;)");
    CHECK(contains(d, "m.mo:6:13: error: 'a' is final and cannot be redeclared"));
  }
  SECTION("a redeclare element with nothing inherited to replace") {
    const std::string d = errors_of(R"(
      model M
        model H Real x = 1; end H;
        model D extends H; redeclare Real z = 2; end D;
        D d;
      end M;)");
    CHECK(contains(d, "m.mo:4:43: error: 'z' is redeclared but no base class declares it"));
  }
  SECTION("a redeclaration of an element the class does not have") {
    const std::string d = errors_of(R"(
      model M
        block A output Real y = 1; end A;
        model H replaceable A a; end H;
        H h(redeclare A b);
      end M;)");
    CHECK(contains(d, "error: modifier 'b' does not name an element of component 'h' of type 'H'"));
  }
  SECTION("a class extension with no inherited class of its name") {
    const std::string d = errors_of(R"(
      model M
        model H Real x = 1; end H;
        model D extends H; redeclare model extends N Real y; end N; N n; end D;
        D d;
      end M;)");
    CHECK(contains(d, "m.mo:4:44: error: class extension 'N': no base of 'M.D' has a class 'N'"));
  }
}

TEST_CASE("an outer element without an enclosing inner one gets a default inner, with a warning",
          "[redeclare][inner]") {
  // As Dymola and OpenModelica do (MLS 5.4 lets tools add it): a Fluid
  // component checked alone has `outer System system` and no inner one.
  const Compiled c = compile({{"m.mo", R"(
    model M
      model E parameter Real k = 2; Real x = k * time; end E;
      model U outer E e; Real y = e.x; end U;
      U u, v;
    end M;)"}});
  REQUIRE(c.ok());
  CHECK(contains(c.diagnostics, "m.mo:4:23: warning: no enclosing instance declares an 'inner' element 'e' for "
                                "this 'outer' one; the model gets one of type 'E' with its default values"));
  CHECK(c.diagnostics.find("warning") == c.diagnostics.rfind("warning")); // one inner for both outers
  const std::string flat = c.model->print();
  CHECK(contains(flat, "parameter Real `e.k` = 2;"));
  CHECK(contains(flat, "`u.y` = `e.x`;"));
  CHECK(contains(flat, "`v.y` = `e.x`;"));
  // The outer of a class the model extends (a component checked alone) too.
  const Compiled own = compile({{"m.mo", R"(
    model M
      model E parameter Real k = 2; Real x = k * time; end E;
      model U outer E e; Real y = e.x; end U;
      extends U;
    end M;)"}});
  REQUIRE(own.ok());
  CHECK(contains(own.model->print(), "y = `e.x`;"));
  // The model's own element of that name is not an inner one: an error.
  const std::string d = errors_of(R"(
    model M
      model E Real x = time; end E;
      model U outer E e; Real y = e.x; end U;
      U u;
      Real e = 1;
    end M;)");
  CHECK(contains(d, "m.mo:4:23: error: no enclosing instance declares an 'inner' element 'e' for this 'outer' one"));
}

TEST_CASE("a redeclared conditional component keeps its declaration's condition", "[redeclare]") {
  // As the MSL's machines: `replaceable Ambient thermalAmbient if not
  // useThermalPort`, redeclared by each machine with its own ambient model.
  const std::string text = R"(
    connector HeatPort Real T; flow Real Q; end HeatPort;
    model Ambient HeatPort port; parameter Real Ta = 300; equation port.T = Ta; end Ambient;
    model CoolAmbient extends Ambient(Ta = 280); end CoolAmbient;
    model Core HeatPort port; equation port.Q = port.T - 290; end Core;
    partial model Machine
      parameter Boolean useThermalPort = false;
      Core core;
      HeatPort thermalPort if useThermalPort;
      replaceable Ambient thermalAmbient if not useThermalPort;
    equation
      connect(core.port, thermalPort);
      connect(core.port, thermalAmbient.port);
    end Machine;
    model Motor extends Machine(redeclare CoolAmbient thermalAmbient); end Motor;
    model Outside
      Motor m(useThermalPort = true);
      Ambient source(Ta = 350);
    equation
      connect(m.thermalPort, source.port);
    end Outside;
    model Inside Motor m; end Inside;)";
  // With the port, the redeclared ambient is switched off with its connection.
  const std::string outside = flat_of("m.mo", text + "\nmodel A extends Outside; end A;");
  CHECK_FALSE(contains(outside, "thermalAmbient"));
  CHECK(contains(outside, "m.thermalPort.T"));
  CHECK(contains(outside, "source.port.T"));
  // Without it, the redeclared ambient is there, with its own temperature.
  const std::string inside = flat_of("m.mo", text + "\nmodel B extends Inside; end B;");
  CHECK(contains(inside, "m.thermalAmbient.Ta` = 280"));
  CHECK_FALSE(contains(inside, "m.thermalPort"));
}
