// Modelica text: minimal parentheses by precedence, names, and the dump.
#include <catch2/catch.hpp>

#include <limits>

#include "mo/symbolic/printer.hpp"

using namespace mo::symbolic;

namespace {
struct Fixture {
  ExprArena A;
  Expr x = A.symbol("x", SymbolRole::State, 0);
  Expr y = A.symbol("y", SymbolRole::State, 1);
  Expr z = A.symbol("z", SymbolRole::Algebraic, 0);
  Expr c(double v) { return A.constant(v); }
  std::string text(Expr e) { return to_modelica(A, e); }
};
} // namespace

TEST_CASE_METHOD(Fixture, "arithmetic prints with minimal parentheses", "[symbolic][printer]") {
  CHECK(text(A.add(x, A.mul(y, z))) == "x + y*z");
  // Operands of commutative operations print in canonical order: older first.
  CHECK(text(A.mul(A.add(x, y), z)) == "z*(x + y)");
  CHECK(text(A.sub(A.sub(x, y), z)) == "x - y - z");
  CHECK(text(A.sub(x, A.sub(y, z))) == "x - (y - z)");
  CHECK(text(A.div(x, A.mul(y, z))) == "x/(y*z)");
  CHECK(text(A.div(A.mul(x, y), z)) == "x*y/z");
  CHECK(text(A.neg(A.mul(x, y))) == "-x*y");
  CHECK(text(A.neg(A.add(x, y))) == "-(x + y)");
  CHECK(text(A.mul(x, A.neg(y))) == "x*(-y)");
  CHECK(text(A.sub(A.neg(x), y)) == "-x - y");
  CHECK(text(A.mul(c(2), x)) == "2*x");
  CHECK(text(A.add(x, c(1))) == "x + 1");
  CHECK(text(A.sub(x, c(2.5))) == "x - 2.5");
  CHECK(text(A.mul(c(1e-10), x)) == "1e-10*x");
}

TEST_CASE_METHOD(Fixture, "powers need primaries on both sides", "[symbolic][printer]") {
  CHECK(text(A.pow(x, c(2))) == "x^2");
  CHECK(text(A.pow(A.pow(x, y), z)) == "(x^y)^z");
  CHECK(text(A.pow(x, A.pow(y, z))) == "x^(y^z)");
  CHECK(text(A.pow(x, c(-1))) == "x^(-1)");
  CHECK(text(A.pow(A.neg(x), c(2))) == "(-x)^2");
  CHECK(text(A.pow(A.mul(x, y), c(2))) == "(x*y)^2");
  CHECK(text(A.pow(A.sin(x), c(2))) == "sin(x)^2");
  // "-2*x" would parse as -(2*x): a negative constant is not a primary.
  CHECK(text(A.mul(c(-2), x)) == "(-2)*x");
  CHECK(text(A.mul(x, A.pow(c(-2), y))) == "x*(-2)^y");
}

TEST_CASE_METHOD(Fixture, "functions, events, der and pre", "[symbolic][printer]") {
  CHECK(text(A.atan2(x, A.add(y, c(1)))) == "atan2(x, y + 1)");
  CHECK(text(A.min(x, y)) == "min(x, y)");
  CHECK(text(A.smooth(1, A.abs(x))) == "smooth(1, abs(x))");
  CHECK(text(A.no_event(A.lt(x, y))) == "noEvent(x < y)");
  const Expr der_x = A.der(x);
  const Expr pre_z = A.pre(z);
  CHECK(text(A.add(pre_z, der_x)) == "der(x) + pre(z)");
  CHECK(text(A.log10(A.sqrt(x))) == "log10(sqrt(x))");
}

TEST_CASE_METHOD(Fixture, "conditions, relations and logic", "[symbolic][printer]") {
  const Expr cond = A.lt(x, y);
  CHECK(text(A.select(cond, x, y)) == "if x < y then x else y");
  CHECK(text(A.add(A.select(cond, x, y), c(1))) == "(if x < y then x else y) + 1");
  CHECK(text(A.select(cond, x, A.select(A.gt(x, z), y, z))) ==
        "if x < y then x else if x > z then y else z");
  CHECK(text(A.select(cond, A.select(A.gt(x, z), y, z), x)) ==
        "if x < y then (if x > z then y else z) else x");
  CHECK(text(A.le(A.neg(x), A.add(y, z))) == "-x <= y + z");
  const Expr a = A.ge(x, c(0));
  const Expr b = A.ne(y, c(0));
  const Expr both = A.logical_and(cond, a);
  const Expr either = A.logical_or(cond, a);
  CHECK(text(A.logical_or(both, b)) == "y <> 0 or x < y and x >= 0");
  CHECK(text(A.logical_or(b, A.logical_not(b))) == "y <> 0 or not y <> 0");
  CHECK(text(A.logical_and(either, b)) == "y <> 0 and (x < y or x >= 0)");
  CHECK(text(A.logical_not(A.logical_and(cond, a))) == "not (x < y and x >= 0)");
  CHECK(text(A.logical_not(cond)) == "not x < y");
  CHECK(text(A.eq(A.lt(x, y), c(1))) == "(x < y) == 1");
}

TEST_CASE_METHOD(Fixture, "names that are not plain references are quoted", "[symbolic][printer]") {
  // Flat names are one identifier each: dotted or subscripted ones are
  // backquoted as Scilab/Xcos writes them; names a backquote cannot hold are
  // single-quoted with escapes.
  CHECK(modelica_name("pendulum.phi") == "`pendulum.phi`");
  CHECK(modelica_name("a.b[1,2].c") == "`a.b[1,2].c`");
  CHECK(modelica_name("_x1") == "_x1");
  CHECK(modelica_name("my var") == "`my var`");
  CHECK(modelica_name("end") == "`end`");
  CHECK(modelica_name("der(x)") == "`der(x)`");
  CHECK(modelica_name("1x") == "`1x`");
  CHECK(modelica_name("it's") == "`it's`");
  CHECK(modelica_name("a`b") == "'a`b'");
  CHECK(modelica_name("new\nline") == "'new\\nline'");
  const Expr odd = A.symbol("my var", SymbolRole::Input, 0);
  CHECK(text(A.mul(c(2), odd)) == "2*`my var`");
}

TEST_CASE_METHOD(Fixture, "non-finite constants print as valid Modelica", "[symbolic][printer]") {
  CHECK(text(c(std::numeric_limits<double>::infinity())) == "Modelica.Constants.inf");
  CHECK(text(A.add(x, c(std::numeric_limits<double>::quiet_NaN()))) == "x + (0.0/0.0)");
}

TEST_CASE_METHOD(Fixture, "the dump lists each distinct node once", "[symbolic][printer]") {
  const Expr s = A.sin(x);
  const Expr e = A.mul(s, s);
  const Expr outs[] = {e, s};
  CHECK(dump_graph(A, outs) == "%0 = x (State 0)\n"
                               "%3 = Sin(%0)\n"
                               "%4 = Mul(%3, %3)\n"
                               "out[0] = %4\n"
                               "out[1] = %3\n");
  CHECK(text(e) == "sin(x)*sin(x)");
}
