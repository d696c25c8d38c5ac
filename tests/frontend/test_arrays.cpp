// Array forms scalarise to the exact flat text pinned beside each model in
// data/arrays/ (NAME.mo → NAME.flat; MO_UPDATE_GOLDEN=1 rewrites them), and
// that text flattens again to itself. The e2e suite simulates the same
// models against their analytic solutions (tests/e2e/test_arrays.cpp).
#include "compile.hpp"

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>

using namespace mo::test;

namespace {
const std::string kArrays = std::string(MO_TEST_DATA_DIR) + "/arrays/";

std::string flat_of(const std::string &name, const std::string &text) {
  Compiled c = compile({{name, text}});
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  CHECK(c.diagnostics.empty());
  return c.model->print();
}
} // namespace

TEST_CASE("every array model flattens to its pinned flat text, which flattens to itself", "[arrays]") {
  auto files = list_files(kArrays, ".mo");
  REQUIRE(files.size() >= 8);
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

TEST_CASE("array equations and slices give one scalar equation per element", "[arrays]") {
  Compiled c = compile_text(read_file(kArrays + "SliceCascade.mo"));
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  // 5 der + 5 running sums + 3 odd elements + 2 column + 3 row + 1 = 19.
  CHECK(c.model->equations.size() == 19);
  const std::string s = c.model->print();
  CHECK(s.find("`s[5]` = `s[4]` + `x[5]`;") != std::string::npos);
  CHECK(s.find("`e[3]` = `x[5]`;") != std::string::npos);
  CHECK(s.find("`c[2]` = `A[2,2]` * `x[2]`;") != std::string::npos);
}

TEST_CASE("array constructors with several iterators: the last one runs along the first dimension", "[arrays]") {
  Compiled c = compile_text(R"(
    model Toeplitz
      parameter Real T[2, 3] = {i - j for i in 1:3, j in 1:2};
    end Toeplitz;)");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  // T[j, i] = i - j
  CHECK(c.model->variables[c.model->find("T[1,3]")].value == 2.0);
  CHECK(c.model->variables[c.model->find("T[2,1]")].value == -1.0);
}

TEST_CASE("fill() of an array repeats it along new leading dimensions", "[arrays]") {
  // The MSL's multi-conductor line (Lines.M_OLine) gives each of its N - 1
  // segments the row of a per-line vector: `segment s[N - 1](Rl = fill(r * length / N, N - 1))`.
  Compiled c = compile_text(R"(
    model Seg
      parameter Integer lines = 3;
      parameter Real Rl[lines] = fill(1, lines);
      Real x[lines](each start = 1, each fixed = true);
    equation
      der(x) = -Rl .* x;
    end Seg;
    model Chain
      parameter Real r[3] = {1, 2, 3};
      parameter Real M[2, 2, 3] = fill(r, 2, 2);
      Seg s[2](lines = fill(3, 2), Rl = fill(r * 2, 2));
    end Chain;)",
                            "Chain");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  CHECK(c.model->variables[c.model->find("M[2,1,3]")].value == 3.0);
  CHECK(c.model->variables[c.model->find("M[1,2,2]")].value == 2.0);
  CHECK(c.model->variables[c.model->find("s[2].Rl[3]")].value == 6.0);
  CHECK(c.model->variables[c.model->find("s[1].Rl[1]")].value == 2.0);
  // The wrong count of rows for the array of components is still reported.
  Compiled short_rows = compile_text(R"(
    model Seg
      parameter Real Rl[3] = fill(1, 3);
    end Seg;
    model Chain
      Seg s[3](Rl = fill({1, 2, 3}, 2));
    end Chain;)",
                                     "Chain");
  CHECK_FALSE(short_rows.ok());
  CHECK(short_rows.diagnostics.find("the binding has 2 elements; element 3 is needed") != std::string::npos);
}

TEST_CASE("array forms with the wrong sizes are reported, not crashed on", "[arrays]") {
  struct Case {
    const char *equation, *message;
  };
  const Case cases[] = {
      {"y = cat(1, A, {1, 2, 3});", "cannot concatenate arrays of sizes [2, 2] and [3]"},
      {"y = [A, {1, 2, 3}];", "cannot concatenate arrays of sizes [2, 2] and [3, 1] along dimension 2"},
      {"y = cat(3, A, A);", "cannot concatenate along dimension 3 of arrays with 2 dimension(s)"},
      {"y = outerProduct(A, x);", "outerProduct() needs two vectors"},
      {"y = linspace(0, 1, 1);", "linspace() needs n >= 2, got 1"},
      {"x[2:3] = x[1:2];", "subscript 3 is out of bounds 1..2 of 'x'"},
      {"x = y[1:2, 1:1];", "the two sides of this equation have different sizes ([2] and [2, 1])"},
      {"x[1] = x;", "different sizes (a scalar and [2])"},
      {"y = skew(x);", "skew() needs a vector of size 3"},
      {"y = diagonal(A);", "diagonal() needs a vector"},
  };
  for (const Case &k : cases) {
    INFO(k.equation);
    Compiled c = compile_text(std::string("model Bad\n  parameter Real A[2, 2] = [1, 2; 3, 4];\n"
                                          "  Real x[2], y[2, 2];\nequation\n  ") +
                              k.equation + "\nend Bad;\n");
    INFO(c.diagnostics);
    CHECK_FALSE(c.ok());
    CHECK(c.diagnostics.find(k.message) != std::string::npos);
  }
}

TEST_CASE("`constraint` is a keyword inside optimization classes and a name elsewhere", "[arrays][parser]") {
  Compiled plain = compile_text(read_file(kArrays + "ConstraintIdentifier.mo"));
  INFO(plain.diagnostics);
  CHECK(plain.ok());
  Compiled opt = compile_text(R"(
    optimization O(objective = x(finalTime), startTime = 0, finalTime = 1)
      Real x(start = 1, fixed = true);
      input Real u;
    equation
      der(x) = u;
    constraint
      u <= 1;
      -u <= 1;
    end O;)");
  INFO(opt.diagnostics);
  REQUIRE(opt.ok());
  REQUIRE(opt.model->optimization);
  CHECK(opt.model->optimization->constraints.size() == 2);
}

TEST_CASE("a UTF-8 byte-order mark at the start of a file is skipped, positions unchanged", "[arrays][parser]") {
  Compiled c = compile_text("\xEF\xBB\xBFmodel M\n  Real x = undefinedName;\nend M;\n");
  CHECK_FALSE(c.ok());
  CHECK(c.diagnostics.find(":2:12: error: unknown component 'undefinedName'") != std::string::npos);
  CHECK(c.diagnostics.find("0xef") == std::string::npos);
}

TEST_CASE("reductions with iterators evaluate in parameter bindings", "[arrays]") {
  Compiled c = compile_text(read_file(kArrays + "ArrayReductions.mo"));
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  CHECK(c.model->variables[c.model->find("total")].value == 10.0);
  CHECK(c.model->variables[c.model->find("weighted")].value == 4.0 + 2 + 9 + 8);
}

TEST_CASE("a function of scalars applied to arrays is called per element (MLS 12.4.6)", "[arrays][functions]") {
  Compiled c = compile_text(R"(
    model Vectorized
      function scale
        input Real x;
        input Real k = 2;
        output Real y;
      algorithm
        y := k*x;
      end scale;
      function dot2 "a vector input: only the extra leading dimension is vectorized"
        input Real a[2];
        input Real b[2];
        output Real y;
      algorithm
        y := a[1]*b[1] + a[2]*b[2];
      end dot2;
      Real v[3] = scale({1, 2, 3}*time);
      Real w[2, 3] = scale({{1, 2, 3}, {4, 5, 6}}*time, 3);
      function weigh "a scalar and a vector: a vector argument of its own size is not sliced"
        input Real x;
        input Real w[2];
        output Real y;
      algorithm
        y := x*(w[1] + w[2]);
      end weigh;
      Real d[3] = dot2({{1, 0}, {0, 1}, {1, 1}}*time, {1, 2});
      Real u[2] = weigh({1, 2}*time, {3, 4});
      Real s[2] = smooth(0, {time, -time});
    end Vectorized;)");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string s = c.model->print();
  CHECK(s.find("`v[3]` = 2 * (3 * time);") != std::string::npos);
  CHECK(s.find("`w[2,1]` = 3 * (4 * time);") != std::string::npos);
  CHECK(s.find("`d[3]` = 1 * time * 1 + 1 * time * 2;") != std::string::npos);
  CHECK(s.find("`s[2]` = smooth(0, -time);") != std::string::npos);
  CHECK(s.find("`u[2]` = 2 * time * (3 + 4);") != std::string::npos);
  // Arguments that disagree on the vectorized dimensions are reported.
  Compiled bad = compile_text(R"(
    model Bad
      function add
        input Real a;
        input Real b;
        output Real y;
      algorithm
        y := a + b;
      end add;
      Real y[2] = add({1, 2}*time, {1, 2, 3});
    end Bad;)");
  CHECK_FALSE(bad.ok());
  CHECK(bad.diagnostics.find("the arguments of a vectorized call have different sizes ([2] and [3])") !=
        std::string::npos);
}

TEST_CASE("a long type extending a type of a built-in takes its attributes (MultiBody's quaternions)", "[arrays]") {
  Compiled c = compile_text(R"(
    model Quaternions
      type Base = Real[4](each unit = "1");
      type Orientation "extends a type of a built-in, with a function inside"
        extends Base;
        function norm2
          input Orientation q;
          output Real r;
        algorithm
          r := q*q;
        end norm2;
      end Orientation;
      Orientation Q(start = {0, 0, 0, 1}, each stateSelect = StateSelect.prefer);
    equation
      der(Q) = {0, 0, 0, 0};
    end Quaternions;)");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string s = c.model->print();
  CHECK(s.find("Real `Q[4]`(start = 1, unit = \"1\", stateSelect = StateSelect.prefer);") != std::string::npos);
}
