// Result tables, atomic CSV/JSON writing (no partial files), summaries.
#include "fixtures.hpp"
#include "mo/runtime/result.hpp"
#include "mo/runtime/simulate.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace mo::runtime;
namespace fs = std::filesystem;

namespace {

// A fresh empty directory under the build tree for one test.
fs::path scratch_dir(const std::string& name) {
  fs::path dir = fs::path(MO_BINARY_DIR) / "runtime-test-output" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::size_t entries(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

}  // namespace

TEST_CASE("ResultTable rows and columns", "[result]") {
  ResultTable table({"x", "y"});
  table.add_row(0.0, std::vector<double>{1.0, 2.0});
  table.add_row(0.5, std::vector<double>{3.0, 4.0});
  CHECK(table.rows() == 2);
  CHECK(table.column("y") == std::vector<double>{2.0, 4.0});
  CHECK(table.at(1, 0) == 3.0);
  CHECK_THROWS_AS(table.column("z"), std::out_of_range);
  CHECK_THROWS_AS(table.add_row(1.0, std::vector<double>{1.0}), std::invalid_argument);
}

TEST_CASE("CSV is written atomically with round-trip precision", "[result]") {
  fs::path dir = scratch_dir("csv");
  ResultTable table({"x", "phi"});
  table.add_row(0.0, std::vector<double>{0.1, -1.0 / 3.0});
  table.add_row(1e-3, std::vector<double>{2.5e10, 0.0});
  fs::path path = dir / "traj.csv";
  write_csv_atomic(path.string(), table);
  CHECK(slurp(path) == "time,x,phi\n0,0.1,-0.3333333333333333\n0.001,2.5e+10,0\n");
  CHECK(entries(dir) == 1);  // no temporary left behind
  CHECK((fs::status(path).permissions() & fs::perms::owner_read) != fs::perms::none);
}

TEST_CASE("A failed write leaves no partial file and keeps the old one", "[result][errors]") {
  fs::path dir = scratch_dir("failure");
  fs::path path = dir / "traj.csv";
  { std::ofstream(path) << "old contents\n"; }

  SECTION("the writer throws half-way") {
    auto half_then_throw = [](std::ostream& out) {
      out << "time,x\n0,1\n";
      throw std::runtime_error("disk on fire");
    };
    CHECK_THROWS_WITH(write_file_atomic(path.string(), half_then_throw), "disk on fire");
  }
  SECTION("the rename fails: the target is a directory") {
    fs::path target = dir / "is_a_dir";
    fs::create_directory(target);
    ResultTable table({"x"});
    table.add_row(0.0, std::vector<double>{1.0});
    CHECK_THROWS_AS(write_csv_atomic(target.string(), table), std::system_error);
    CHECK(fs::is_directory(target));
    CHECK(fs::is_empty(target));
    fs::remove(target);
  }
  SECTION("the directory does not exist") {
    ResultTable table({"x"});
    CHECK_THROWS_AS(write_csv_atomic((dir / "missing" / "t.csv").string(), table),
                    std::system_error);
  }
  CHECK(slurp(path) == "old contents\n");
  CHECK(entries(dir) == 1);  // only traj.csv: no temporaries
}

TEST_CASE("JSON summary of a simulation", "[result]") {
  fixtures::BouncingBall model;
  auto result = simulate(model, Inputs{}, model.info().default_parameters(),
                         OutputGrid::uniform(0, 1.5, 10));  // bounces at 0.45 and 1.17
  REQUIRE(result.ok());
  fs::path path = scratch_dir("json") / "summary.json";
  write_summary_json(path.string(), result);
  auto j = nlohmann::json::parse(slurp(path));
  CHECK(j["status"] == "success");
  CHECK(j["statistics"]["steps"].get<long>() == result.statistics.steps);
  CHECK(j["statistics"]["events"].get<long>() == 2);
  CHECK(j["event_times"].size() == 2);
  CHECK(j["timings"]["wall_time_seconds"].get<double>() >= 0.0);
  CHECK(j["columns"] == nlohmann::json::array({"h", "v", "height"}));
  CHECK(j["rows"] == 11);
}

TEST_CASE("Sensitivities as a named table, written as CSV", "[result]") {
  fixtures::LinearDecay model;
  SimulationOptions o;
  o.sensitivities.method = SensitivityMethod::cvodes_analytic;
  o.sensitivities.parameters = {1};
  Inputs inputs;
  inputs.add(constant_input(0.0));
  auto result = simulate(model, inputs, model.info().default_parameters(),
                         OutputGrid::uniform(0, 1, 4), o);
  REQUIRE(result.ok());
  ResultTable table = sensitivity_table(result, model.info());
  CHECK(table.names() ==
        std::vector<std::string>{"d(a)/d(a0)", "d(b)/d(a0)", "d(a_out)/d(a0)", "d(kb)/d(a0)"});
  REQUIRE(table.rows() == 5);
  CHECK(table.at(0, 0) == 1.0);  // S(0) = ∂x0/∂a0
  CHECK(table.at(4, 0) == Approx(std::exp(-2.0)).epsilon(1e-5));
  fs::path path = scratch_dir("sens") / "sens.csv";
  write_csv_atomic(path.string(), table);
  CHECK(slurp(path).rfind("time,d(a)/d(a0),d(b)/d(a0),d(a_out)/d(a0),d(kb)/d(a0)\n0,1,0,1,0\n", 0) == 0);
  CHECK(sensitivity_table(simulate(model, inputs, model.info().default_parameters(),
                                   OutputGrid::uniform(0, 1, 4)),
                          model.info())
            .rows() == 0);
}
