// Expressions print with the fewest parentheses that keep their structure:
// printing, parsing and printing again is stable.
#include "compile.hpp"
#include "mo/frontend/printer.hpp"

#include <catch2/catch.hpp>

using namespace mo::test;

namespace {
std::string reprint(const std::string &rhs) {
  Compiled c = compile_text("model M Real a, b, c, x; equation x = " + rhs +
                            "; a = 1; b = 2; c = 3; end M;");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  return mo::frontend::print_expr(*c.model->equations[0].rhs,
                                  [&](std::int32_t v) { return c.model->variables[v].name; });
}
} // namespace

TEST_CASE("printer keeps structure with minimal parentheses", "[printer]") {
  CHECK(reprint("(a + b) * c") == "(a + b) * c");
  CHECK(reprint("a + (b + c)") == "a + (b + c)");
  CHECK(reprint("a - (b - c)") == "a - (b - c)");
  CHECK(reprint("(a - b) - c") == "a - b - c");
  CHECK(reprint("a * (-b)") == "a * (-b)");
  CHECK(reprint("-a * b") == "-a * b");
  CHECK(reprint("(-a) * b") == "(-a) * b");
  CHECK(reprint("a ^ (-2)") == "a^(-2)");
  CHECK(reprint("(a ^ b) ^ c") == "(a^b)^c");
  CHECK(reprint("if a > b then (if b > c then 1 else 2) else 3") ==
        "if a > b then if b > c then 1 else 2 else 3");
  CHECK(reprint("a + (if a > b then 1 else 2)") == "a + (if a > b then 1 else 2)");
  CHECK(reprint("1e-05 * a") == "1e-05 * a");
  CHECK(reprint("10. * a") == "10. * a");
}

TEST_CASE("numbers print so that they read back exactly", "[printer]") {
  using mo::frontend::format_real;
  CHECK(format_real(10) == "10.");
  CHECK(format_real(0.1) == "0.1");
  CHECK(format_real(6.283185307179586) == "6.283185307179586");
  CHECK(std::stod(format_real(9.999999999999999e-12)) == 9.999999999999999e-12);
  CHECK(std::stod(format_real(1.0 / 3.0)) == 1.0 / 3.0);
}

TEST_CASE("identifiers are quoted only when they must be", "[printer]") {
  using mo::frontend::quote_name;
  CHECK(quote_name("x") == "x");
  CHECK(quote_name("R1.p.v") == "`R1.p.v`");
  CHECK(quote_name("n_12.[2]") == "`n_12.[2]`");
  CHECK(quote_name("'my var'") == "'my var'");
  CHECK(quote_name("end") == "`end`");
}

TEST_CASE("same_expr compares structure, names and numbers, not source ranges", "[printer]") {
  using namespace mo::frontend::ast;
  auto sum = [](double k, const char *name) {
    std::vector<ExprPtr> args;
    args.push_back(make_binary(Op::Mul, make_real(k), make_ref(name)));
    return make_call("sin", std::move(args));
  };
  ExprPtr a = sum(2, "x"), b = sum(2, "x");
  b->range.begin = 40; // ranges differ
  CHECK(same_expr(*a, *b));
  CHECK(same_expr(*a, *a->clone()));
  CHECK_FALSE(same_expr(*a, *sum(3, "x")));
  CHECK_FALSE(same_expr(*a, *sum(2, "y")));
  ExprPtr c = sum(2, "x");
  c->ref.parts[0].name = "cos";
  CHECK_FALSE(same_expr(*a, *c));
  CHECK_FALSE(same_expr(*make_binary(Op::Add, make_real(1), make_real(2)),
                        *make_binary(Op::Sub, make_real(1), make_real(2))));
}
