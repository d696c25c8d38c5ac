// Records in expressions (MLS 12.6; flatten_records.cpp): a record's
// binding binds its fields, a record passes through functions, and what
// Modelica rejects is reported at its source. The simulation of
// tests/e2e/data/Records.mo against closed forms is in tests/e2e/test_records.cpp.
#include "compile.hpp"

#include <catch2/catch.hpp>

using namespace mo::test;

namespace {

const char *kPt = R"(
record Pt
  Real x;
  Real y = 2 * x; // a default that reads a field before it
end Pt;
)";

Compiled with_pt(const std::string &model) { return compile({{"Pt.mo", kPt}, {"M.mo", model}}, "M"); }

/// The flat model's text; REQUIREs that it compiled.
std::string printed_model(const Compiled &c) {
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  return c.model->print();
}

} // namespace

TEST_CASE("records: a binding binds each field - a constructor's default reads the fields before it",
          "[flatten][records]") {
  Compiled c = with_pt(R"(
model M
  parameter Pt a = Pt(3);
  parameter Pt b[2] = {Pt(1, 5), a};
  parameter Pt m(x = 7) = a; // a field's own modifier wins over the record's binding
  Pt v = Pt(x = time);
end M;
)");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string s = c.model->print();
  INFO(s);
  for (const char *line : {"parameter Real `a.x` = 3;", "parameter Real `m.x` = 7;", "parameter Real `m.y` = `a.y`;", "parameter Real `a.y` = 2 * 3;",
                           "parameter Real `b[1].y` = 5;", "parameter Real `b[2].x` = `a.x`;",
                           "parameter Real `b[2].y` = `a.y`;", "`v.x` = time;", "`v.y` = 2 * time;"})
    CHECK(s.find(line) != std::string::npos);
}

TEST_CASE("records: an equation between records is one equation per field", "[flatten][records]") {
  Compiled c = compile_text(R"(
model M
  record P
    Real x;
    Real y;
  end P;
  function mirror
    input P p;
    output P q;
  algorithm
    q := P(p.y, p.x);
  end mirror;
  P u(x(start = 1, fixed = true));
  P w;
equation
  der(u.x) = -u.x;
  u.y = 2 * u.x;
  w = mirror(u);
end M;
)", "M");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string s = c.model->print();
  INFO(s);
  CHECK(s.find("`u.y` = 2 * `u.x`;") != std::string::npos);
  CHECK(s.find("`w.x` = `u.y`;") != std::string::npos);
  CHECK(s.find("`w.y` = `u.x`;") != std::string::npos);
}

TEST_CASE("records: misuse is reported where it is written", "[flatten][records]") {
  const std::pair<const char *, const char *> cases[] = {
      {"  Real r = p + 1;", "a record of type 'Pt' cannot be an operand of '+'"},
      {"  Real r = sum(p);", "a record of type 'Pt' cannot be an operand of sum()"},
      {"  Real r = -p;", "cannot be an operand of '-'"},
      {"  Real r = p;", "a record is bound to a number"},
      {"  Pt q = Pt(1, 2, 3);", "record constructor Pt() takes 2 argument(s), 3 given"},
      {"  Pt q = Pt(y = 1);", "field 'x' of record 'Pt' has no value and no default"},
      {"  Pt q = Pt(1, x = 2);", "input 'x' of record constructor Pt() is given twice"},
      {"  Pt q = Pt(z = 2);", "record constructor Pt() has no input named 'z'"},
      {"  Pt q = 2;", "a value that is not a record is used as one (no field 'x')"},
      {"  Real r = {p, 1} * {1, 1};", "the elements of this array are records of different types"},
  };
  for (const auto &[line, message] : cases) {
    Compiled c = with_pt(std::string("model M\n  parameter Pt p(x = 1);\n") + line + "\nend M;\n");
    INFO(line << "\n" << c.diagnostics);
    CHECK_FALSE(c.ok());
    CHECK(c.diagnostics.find(message) != std::string::npos);
    CHECK(c.diagnostics.find("M.mo:3:") != std::string::npos);
  }
}

TEST_CASE("records: what a package's record constant cannot be given is reported where it is written",
          "[flatten][records]") {
  const std::pair<const char *, const char *> cases[] = {
      {"    constant Pt c(y = 1);", "field 'x' of record 'Pt' has no value and no default"},
      {"    constant Pt c[2](x = 1);", "array of record constants 'c': only 'each' modifiers of its fields"},
      {"    constant Pt c(x(unit = \"m\") = 1);", "record constant 'c': only modifiers that bind a field"},
  };
  for (const auto &[line, message] : cases) {
    Compiled c = with_pt(std::string("model M\n  package P\n") + line + "\n  end P;\n  Real r = P.c[1].y;\nend M;\n");
    INFO(line << "\n" << c.diagnostics);
    CHECK_FALSE(c.ok());
    CHECK(c.diagnostics.find(message) != std::string::npos);
  }
}

TEST_CASE("records: fields of a local record in a function are read and assigned", "[flatten][records]") {
  // f's last assignment is `s := t.x + t.y` plus `extra`.
  const auto with_f = [](const std::string &extra) {
    return with_pt(R"(
model M
  function f
    input Pt p[2];
    output Real s;
  protected
    Pt t;
  algorithm
    t.x := p[2].x;
    t.y := p[1].y;
    s := t.x + t.y)" + extra + R"(;
  end f;
  Real r = f({Pt(1, 2), Pt(3, 4)});
end M;
)");
  };
  Compiled c = with_f(" + p[1].q");
  INFO(c.diagnostics);
  CHECK_FALSE(c.ok());
  CHECK(c.diagnostics.find("record 'Pt' has no field 'q'") != std::string::npos);
  Compiled ok = with_f("");
  INFO(ok.diagnostics);
  REQUIRE(ok.ok());
  CHECK(ok.model->print().find("r = 5;") != std::string::npos);
}

TEST_CASE("a record constructor takes its defaults from the record's extends modifiers", "[records]") {
  // The MSL's hysteresis tables: `record M330_50A extends BaseData(tabris =
  // [...])`, tabris declared [:, :] with another default in BaseData.
  Compiled c = compile_text(R"(
    record Base
      parameter Real a = 1;
      parameter Real t[:, :] = [1, 2];
    end Base;
    record Derived
      extends Base(a = 5, t = [1, 2; 3, 4; 5, 6]);
    end Derived;
    record Scaled
      extends Base(a = 7);
    end Scaled;
    function total
      input Derived r;
      output Real y;
    algorithm
      y := r.a + sum(r.t);
    end total;
    function first
      input Scaled r;
      output Real y;
    algorithm
      y := r.a + r.t[1, 2];
    end first;
    model R
      parameter Real s = total(Derived());
      parameter Real f = first(Scaled());
      Real x(start = 0, fixed = true);
    equation
      der(x) = s + f;
    end R;)", "R");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string flat = c.model->print();
  INFO(flat);
  CHECK(flat.find("parameter Real s = 26;") != std::string::npos);
  CHECK(flat.find("parameter Real f = 9;") != std::string::npos);
}

TEST_CASE("a record component's [:, :] field takes its size from the record's binding", "[records]") {
  // The MSL's GenericHystTellinenTable: `parameter BaseData mat = BaseData()`
  // with `mat = M330_50A()` from outside, tabris declared [:, :]: the field
  // was sized from the whole record value, not from its own part of it.
  const std::string source = R"(
    record Base
      parameter Real[:, :] tab = [1, 2; 3, 4];
      parameter Real k = 1;
    end Base;
    record Big
      extends Base(tab = [1, 2; 3, 4; 5, 6], k = 2);
    end Big;
    model M
      parameter Base mat = Base();
      Real y = mat.tab[size(mat.tab, 1), 2] * mat.k * time;
    end M;
    model Use
      M m(mat = Big());
    end Use;)";
  Compiled own = compile_text(source, "M");
  INFO(own.diagnostics);
  REQUIRE(own.ok());
  CHECK(own.model->print().find("y = `mat.tab[2,2]` * `mat.k` * time;") != std::string::npos);
  Compiled modified = compile_text(source, "Use");
  INFO(modified.diagnostics);
  REQUIRE(modified.ok());
  const std::string text = modified.model->print();
  CHECK(text.find("parameter Real `m.mat.tab[3,2]` = 6;") != std::string::npos);
  CHECK(text.find("parameter Real `m.mat.k` = 2;") != std::string::npos);
  CHECK(text.find("`m.y` = `m.mat.tab[3,2]` * `m.mat.k` * time;") != std::string::npos);
}

// Operator records (MLS 14; flatten_operators.cpp): a dual number with its
// own operators, the way the MSL's Complex is written (an operator holding
// several functions, operator functions, a constructor with a default, an
// output bound field by field).
namespace {

const char *kDual = R"(
operator record Dual "a + b eps, eps^2 = 0"
  Real a;
  Real b;
  encapsulated operator 'constructor'
    function fromReal
      import Dual;
      input Real a;
      input Real b = 0;
      output Dual result(a = a, b = b);
    algorithm
    end fromReal;
  end 'constructor';
  encapsulated operator '-'
    function negate
      import Dual;
      input Dual x;
      output Dual y;
    algorithm
      y := Dual(-x.a, -x.b);
    end negate;
    function subtract
      import Dual;
      input Dual x;
      input Dual z;
      output Dual y;
    algorithm
      y := Dual(x.a - z.a, x.b - z.b);
    end subtract;
  end '-';
  encapsulated operator function '+'
    import Dual;
    input Dual x;
    input Dual z;
    output Dual y;
  algorithm
    y := Dual(x.a + z.a, x.b + z.b);
  end '+';
  encapsulated operator function '*'
    import Dual;
    input Dual x;
    input Dual z;
    output Dual y;
  algorithm
    y := Dual(x.a * z.a, x.a * z.b + x.b * z.a);
  end '*';
  encapsulated operator function '=='
    import Dual;
    input Dual x;
    input Dual z;
    output Boolean same;
  algorithm
    same := x.a == z.a and x.b == z.b;
  end '==';
end Dual;
)";

} // namespace

TEST_CASE("operator records: operators and the constructor call the record's functions", "[flatten][records]") {
  Compiled c = compile({{"Dual.mo", kDual}, {"M.mo", R"(
model M
  Dual x = Dual(time, 1);
  Dual square = x * x;          // (t + eps)^2 = t^2 + 2t eps
  Dual shifted = 3 + x - Dual(1); // a number converted by the constructor
  Dual minus = -x;
  Boolean same = x == Dual(2, 1);
end M;
)"}},
                       "M");
  const std::string printed = printed_model(c);
  INFO(printed);
  for (const char *eq : {"  `x.a` = time;\n", "  `x.b` = 1;\n", "  `square.a` = `x.a` * `x.a`;\n",
                         "  `square.b` = `x.a` * `x.b` + `x.b` * `x.a`;\n", "  `shifted.a` = 3 + `x.a` - 1;\n",
                         "  `shifted.b` = 0 + `x.b` - 0;\n", "  `minus.a` = -`x.a`;\n", "  `minus.b` = -`x.b`;\n",
                         "  same = `x.a` == 2 and `x.b` == 1;\n"})
    CHECK(printed.find(eq) != std::string::npos);
}

TEST_CASE("operator records: an operator the record does not define is reported", "[flatten][records]") {
  Compiled c = compile({{"Dual.mo", kDual}, {"M.mo", R"(
model M
  Dual x = Dual(time, 1);
  Dual q = x / x;
  Dual r = x + {1, 2};
end M;
)"}},
                       "M");
  CHECK_FALSE(c.ok());
  CHECK(c.diagnostics.find("M.mo:4:12: error: no function of operator '/' of 'Dual' takes Dual and Dual (the record "
                           "defines no such operator)") != std::string::npos);
  CHECK(c.diagnostics.find("M.mo:5:12: error: no function of operator '+' of 'Dual' takes Dual and an array")
        != std::string::npos);
}

TEST_CASE("a connector of a record type joins the records field by field", "[flatten][records]") {
  Compiled c = compile({{"Dual.mo", kDual}, {"M.mo", R"(
connector DualInput = input Dual;
connector DualOutput = output Dual;
block Source
  DualOutput y;
equation
  y = Dual(time, 1);
end Source;
block Twice
  DualInput u;
  DualOutput y;
equation
  y = u + u;
end Twice;
model M
  Source s;
  Twice t;
equation
  connect(s.y, t.u);
end M;
)"}},
                       "M");
  const std::string printed = printed_model(c);
  INFO(printed);
  CHECK(printed.find("  `s.y.a` = `t.u.a`;\n") != std::string::npos);
  CHECK(printed.find("  `s.y.b` = `t.u.b`;\n") != std::string::npos);
  CHECK(printed.find("  `t.y.a` = `t.u.a` + `t.u.a`;\n") != std::string::npos);
}

namespace {

/// A pin with an overdetermined reference angle, as QuasiStationary's: its
/// equalityConstraint has no residue.
const char *kRefPin = R"(
record Ref
  Real theta;
  function equalityConstraint
    input Ref r1;
    input Ref r2;
    output Real residue[0];
  algorithm
  end equalityConstraint;
end Ref;
connector Pin
  Real v;
  flow Real i;
  Ref reference;
end Pin;
)";

} // namespace

TEST_CASE("a loop of Connections.branch alone is reported - only a connection may close a loop", "[flatten]") {
  Compiled c = compile({{"RefPin.mo", kRefPin}, {"M.mo", R"(
model Twice "two branches between the same references"
  Pin p(reference(theta = 0));
  Pin n;
equation
  Connections.root(p.reference);
  Connections.branch(p.reference, n.reference);
  Connections.branch(n.reference, p.reference);
  n.reference.theta = p.reference.theta;
  p.i + n.i = 0;
  p.v = n.v;
end Twice;
)"}},
                       "Twice");
  CHECK_FALSE(c.ok());
  CHECK(c.diagnostics.find("error: this Connections.branch closes a loop of branches ('n.reference' and "
                           "'p.reference' are joined by branches already)") != std::string::npos);
}

TEST_CASE("connections between two definite roots are broken - each tree has one root", "[flatten]") {
  Compiled c = compile({{"RefPin.mo", kRefPin}, {"M.mo", R"(
model Source "a root of the graph, its two pins joined by a branch"
  parameter Real w = 1;
  Pin p;
  Pin n;
equation
  Connections.root(p.reference);
  Connections.branch(p.reference, n.reference);
  p.reference.theta = w * time;
  n.reference.theta = p.reference.theta;
  p.i + n.i = 0;
  p.v - n.v = 1;
end Source;
model Sink "a second root, joined to the first by two connections"
  Source a;
  Source b(w = 2);
equation
  connect(a.p, b.p);
  connect(a.n, b.n);
end Sink;
)"}},
                       "Sink");
  const std::string printed = printed_model(c);
  INFO(printed);
  CHECK(printed.find("`a.p.reference.theta` = `b.p.reference.theta`") == std::string::npos);
  CHECK(printed.find("`a.n.reference.theta` = `b.n.reference.theta`") == std::string::npos);
  CHECK(printed.find("  `a.p.v` = `b.p.v`;\n") != std::string::npos);
}

// The MSL's QuasiStationary Delta connects its pins in a polygon by
// `for j loop if j < m then connect(...) else connect(...)`: the connections
// inside the if-equation close loops of the graph too, and are broken.
TEST_CASE("connect()s inside an if-equation close loops of the connection graph too", "[flatten]") {
  Compiled c = compile({{"RefPin.mo", kRefPin}, {"M.mo", R"(
model Element "a branch between its two pins"
  Pin p;
  Pin n;
equation
  Connections.branch(p.reference, n.reference);
  n.reference.theta = p.reference.theta;
  p.i + n.i = 0;
  p.v - n.v = p.i;
end Element;
model Ground
  Pin p;
equation
  Connections.root(p.reference);
  p.reference.theta = 0;
  p.v = 0;
end Ground;
model Polygon "three elements in a ring, grounded"
  parameter Integer m = 3;
  Element e[m];
  Ground g;
equation
  connect(g.p, e[1].p);
  for j in 1:m loop
    if j < m then
      connect(e[j].n, e[j + 1].p);
    else
      connect(e[j].n, e[1].p);
    end if;
  end for;
end Polygon;
)"}},
                       "Polygon");
  const std::string printed = printed_model(c);
  INFO(printed);
  // The ring's last connection closes the loop: no theta equation, its
  // potential and flow equations stay (in the ground's connection set).
  CHECK(printed.find("`e[3].n.reference.theta` = `e[1].p.reference.theta`") == std::string::npos);
  CHECK(printed.find("`e[3].n.reference.theta`") != std::string::npos);
  CHECK(printed.find("`e[1].n.reference.theta` = `e[2].p.reference.theta`") != std::string::npos);
  CHECK(printed.find("`g.p.v` = `e[3].n.v`") != std::string::npos);
  CHECK(printed.find("`g.p.i` + `e[1].p.i` + `e[3].n.i` = 0.") != std::string::npos);
}

TEST_CASE("a connect() inside an if-equation with an error is reported once", "[flatten]") {
  Compiled c = compile({{"RefPin.mo", kRefPin}, {"M.mo", R"(
model Bad
  parameter Boolean on = true;
  Pin a;
  Pin b;
equation
  if on then
    connect(a, nowhere);
  end if;
end Bad;
)"}},
                       "Bad");
  CHECK_FALSE(c.ok());
  const std::string& d = c.diagnostics;
  INFO(d);
  const auto first = d.find("unknown connector 'nowhere'");
  REQUIRE(first != std::string::npos);
  CHECK(d.find("unknown connector 'nowhere'", first + 1) == std::string::npos);
}

// SIunits.ComplexVoltage is `operator record ComplexVoltage = Complex(redeclare
// Voltage re, redeclare Voltage im)`: a field the short class redeclares takes
// its part of the record's binding like any other.
TEST_CASE("a record binding binds the fields its type redeclares", "[flatten][records]") {
  Compiled c = compile({{"Dual.mo", kDual}, {"M.mo", R"(
type Length = Real(unit = "m");
record Pair
  replaceable Real a;
  replaceable Real b;
end Pair;
record LengthPair = Pair(redeclare Length a, redeclare Length b);
model M
  LengthPair p = Pair(time, 2);
  Pair q = p;
end M;
)"}},
                       "M");
  const std::string printed = printed_model(c);
  INFO(printed);
  CHECK(printed.find("  Real `p.a`(unit = \"m\");\n") != std::string::npos);
  CHECK(printed.find("  `p.a` = time;\n") != std::string::npos);
  CHECK(printed.find("  `p.b` = 2;\n") != std::string::npos);
  CHECK(printed.find("  `q.a` = `p.a`;\n") != std::string::npos);
}

TEST_CASE("arrays of operator records - element-wise operators and vectorized calls and fill",
          "[flatten][records]") {
  Compiled c = compile({{"Dual.mo", kDual}, {"M.mo", R"(
function real
  input Dual x;
  output Real y = x.a;
algorithm
end real;
model M
  parameter Boolean flip[2] = {false, true};
  Dual d[2] = {Dual(time, 1), Dual(2, time)};
  Dual s[2] = d + d;
  Dual t[2] = 2 * d;
  Dual n[2] = -d;
  Dual z[2] = fill(Dual(0), 2);
  Dual w[2] = {if flip[k] then -d[k] else d[k] for k in 1:2};
  Real r[2] = real(d);
end M;
)"}},
                       "M");
  const std::string printed = printed_model(c);
  INFO(printed);
  for (const char *eq : {"  `s[2].a` = `d[2].a` + `d[2].a`;\n", "  `t[1].b` = 2 * `d[1].b` + 0 * `d[1].a`;\n",
                         "  `n[2].b` = -`d[2].b`;\n", "  `z[2].a` = 0;\n", "  `z[1].b` = 0;\n",
                         "  `w[2].a` = if `flip[2]` then -`d[2].a` else `d[2].a`;\n", "  `r[2]` = `d[2].a`;\n"})
    CHECK(printed.find(eq) != std::string::npos);
}
