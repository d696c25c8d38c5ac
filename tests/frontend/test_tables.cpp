// External objects and the tables mocompile provides for them
// (frontend/src/flatten_tables.cpp): files, and what is refused. The
// simulations against closed forms are in tests/e2e/test_tables.cpp.
#include "compile.hpp"

#include <catch2/catch.hpp>

#include <filesystem>

#include <unistd.h>

using namespace mo::test;
namespace fs = std::filesystem;

namespace {

Compiled tables(const std::string &cls, const std::string &extra) {
  const std::string text = read_file(std::string(MO_SOURCE_DIR) + "/tests/e2e/data/Tables.mo");
  return compile({{"Tables.mo", text}, {"Extra.mo", extra}}, cls);
}

} // namespace

TEST_CASE("a table is read from a text file in ModelicaStandardTables' format", "[flatten][tables]") {
  const fs::path dir = fs::temp_directory_path() / ("mo_tables_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "profile.txt";
  write_file(file.string(), "#1\n# a comment\ndouble other(1,2)\n 0 9\ndouble profile(3, 2)  # time, value\n"
                            "0 1.25\n2, 7.75\n4\t-3.5\n");
  Compiled c = tables("FromFile", R"(
model FromFile
  Tables.Source s(table = fill(0.0, 0, 2), fileName = ")" + file.string() + R"(", tableName = "profile");
  Real x(start = 0, fixed = true);
equation
  der(x) = s.y;
end FromFile;
)");
  INFO(c.diagnostics);
  REQUIRE(c.ok());
  const std::string s = c.model->print();
  for (const char *v : {"1.25", "7.75", "-3.5"})
    CHECK(s.find(v) != std::string::npos);
  CHECK(s.find(" 9") == std::string::npos); // the other table's value

  // A model with nothing but a source reading table `name` of the file.
  auto source_of = [&](const std::string &name) {
    return tables("Reads", "model Reads\n  Tables.Source s(table = fill(0.0, 0, 2), fileName = \"" + file.string() +
                               "\", tableName = \"" + name + "\");\nend Reads;\n");
  };
  Compiled missing = source_of("nothere");
  CHECK_FALSE(missing.ok());
  CHECK(missing.diagnostics.find("no table 'double nothere(rows, columns)'") != std::string::npos);

  write_file(file.string(), "#1\ndouble profile(2, 2)\n0 1\n1 nan\n");
  Compiled nan = source_of("profile");
  CHECK_FALSE(nan.ok());
  CHECK(nan.diagnostics.find("'nan' in table 'profile'") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("tables: a spline's jump, decreasing times and unknown constructors are refused", "[flatten][tables]") {
  Compiled spline = tables("Jump", R"(
model Jump
  Tables.Source s(table = [0, 0; 1, 1; 1, 2; 2, 0], smoothness = 2);
end Jump;
)");
  CHECK_FALSE(spline.ok());
  CHECK(spline.diagnostics.find("a spline (ContinuousDerivative) needs strictly increasing keys (1 twice)") !=
        std::string::npos);

  Compiled backwards = tables("Backwards", R"(
model Backwards
  Tables.Source s(table = [0, 0; 2, 1; 1, 0]);
end Backwards;
)");
  CHECK_FALSE(backwards.ok());
  const std::string once = "its first column must increase (1 after 2)";
  CHECK(backwards.diagnostics.find(once) != std::string::npos);
  CHECK(backwards.diagnostics.find(once, backwards.diagnostics.find(once) + 1) == std::string::npos);

  Compiled unknown = compile_text(R"(
class Handle
  extends ExternalObject;
  function constructor
    input Real x;
    output Handle h;
  external "C" h = my_init(x);
  end constructor;
  function destructor
    input Handle h;
  external "C" my_close(h);
  end destructor;
end Handle;
function get
  input Handle h;
  output Real y;
external "C" y = my_get(h);
end get;
model UsesHandle
  Handle h = Handle(1.0);
  Real y = get(h);
end UsesHandle;
)", "UsesHandle");
  CHECK_FALSE(unknown.ok());
  CHECK(unknown.diagnostics.find("external function 'get' (language \"C\") cannot be evaluated") != std::string::npos);
}
