// MATLAB .mat files read as result tables: files written here with matio in
// versions 4, 5 and 7.3, as plain vectors and in Dymola's result layout (one
// variable per row, and per column as Dymola's binTrans writes them).
#include "mo/runtime/input.hpp"
#include "mo/runtime/mat_file.hpp"

#include <catch2/catch.hpp>
#include <matio.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace mo::runtime;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  fs::path dir = fs::path(MO_BINARY_DIR) / "runtime-test-output" / "mat" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// A .mat file being written: numeric matrices and char matrices given row by row.
class MatWriter {
public:
  MatWriter(const fs::path& path, mat_ft version) : mat_(Mat_CreateVer(path.c_str(), nullptr, version)) {
    REQUIRE(mat_ != nullptr);
  }
  ~MatWriter() { Mat_Close(mat_); }
  MatWriter(const MatWriter&) = delete;
  MatWriter& operator=(const MatWriter&) = delete;

  /// `rows`×`cols` doubles given row-major (stored column-major, as MATLAB does).
  void numbers(const char* name, std::size_t rows, std::size_t cols, const std::vector<double>& row_major) {
    std::vector<double> data(rows * cols);
    for (std::size_t r = 0; r < rows; ++r)
      for (std::size_t c = 0; c < cols; ++c) data[c * rows + r] = row_major[r * cols + c];
    write(name, MAT_C_DOUBLE, MAT_T_DOUBLE, rows, cols, data.data());
  }
  /// A char matrix with one row per string, padded with blanks.
  void text(const char* name, const std::vector<std::string>& rows) {
    std::size_t cols = 0;
    for (const auto& s : rows) cols = std::max(cols, s.size());
    std::vector<char> data(rows.size() * cols, ' ');
    for (std::size_t r = 0; r < rows.size(); ++r)
      for (std::size_t c = 0; c < rows[r].size(); ++c) data[c * rows.size() + r] = rows[r][c];
    write(name, MAT_C_CHAR, MAT_T_UINT8, rows.size(), cols, data.data());
  }

private:
  void write(const char* name, matio_classes cls, matio_types type, std::size_t rows, std::size_t cols,
             void* data) {
    std::size_t dims[2] = {rows, cols};
    matvar_t* v = Mat_VarCreate(name, cls, type, 2, dims, data, 0);
    REQUIRE(v != nullptr);
    CHECK(Mat_VarWrite(mat_, v, MAT_COMPRESSION_NONE) == 0);
    Mat_VarFree(v);
  }
  mat_t* mat_;
};

/// Strings as the columns of a char matrix (Dymola's binTrans `name`).
std::vector<std::string> as_columns(const std::vector<std::string>& strings) {
  std::size_t len = 0;
  for (const auto& s : strings) len = std::max(len, s.size());
  std::vector<std::string> rows(len, std::string(strings.size(), ' '));
  for (std::size_t c = 0; c < strings.size(); ++c)
    for (std::size_t r = 0; r < strings[c].size(); ++r) rows[r][c] = strings[c][r];
  return rows;
}

const std::vector<double>& column(const InputTable& t, const std::string& name) {
  for (std::size_t k = 0; k < t.names.size(); ++k)
    if (t.names[k] == name) return t.columns[k];
  FAIL("no column " << name);
  return t.columns.front();
}

// time, x = 1 + t, p = 2 (parameter, data_1), y = −x (alias, dataInfo column −2)
const std::vector<std::string> kNames = {"time", "x", "p", "y"};
const std::vector<double> kInfo = {0, 1, 0, -1,  2, 2, 0, -1,  1, 2, 0, 0,  2, -2, 0, -1};  // 4 per variable
const std::vector<double> kTimes = {0, 0.5, 1, 1, 2};

void check_dymola(const InputTable& t) {
  CHECK(t.times == kTimes);
  REQUIRE(t.names == std::vector<std::string>{"x", "p", "y"});
  for (std::size_t k = 0; k < kTimes.size(); ++k) {
    CHECK(column(t, "x")[k] == Approx(1 + kTimes[k]));
    CHECK(column(t, "y")[k] == Approx(-1 - kTimes[k]));
    CHECK(column(t, "p")[k] == 2.0);
  }
}

}  // namespace

TEST_CASE("mat files: plain vectors beside time, versions 5 and 7.3", "[input][mat]") {
  for (const auto version : {MAT_FT_MAT5, MAT_FT_MAT73}) {
    INFO("version " << static_cast<int>(version));
    const fs::path path = scratch("vectors") / "data.mat";
    {
      MatWriter w(path, version);
      w.numbers("x", 3, 1, {1, 2, 4});           // column vector
      w.numbers("time", 1, 3, {0, 1, 2});        // row vector
      w.numbers("other", 1, 2, {7, 8});          // another length: not a column
      w.numbers("grid", 3, 3, std::vector<double>(9, 0.0));  // a matrix: not a column
      w.text("label", {"abc"});
    }
    CHECK(is_mat_file(path.string()));
    const InputTable t = read_result_table(path.string());
    CHECK(t.times == std::vector<double>{0, 1, 2});
    REQUIRE(t.names == std::vector<std::string>{"x"});
    CHECK(t.columns[0] == std::vector<double>{1, 2, 4});
    // The table drives an input signal: linear between samples.
    auto shared = std::make_shared<const InputTable>(t);
    CHECK(table_input(shared, "x")->value(1.5) == Approx(3.0));
  }
}

TEST_CASE("mat files: Dymola's result layout, per row (v5, v7.3) and per column (v4, binTrans)", "[input][mat]") {
  // One variable per row: name(4, len), dataInfo(4, 4), data_1(2, 2), data_2(5, 3).
  for (const auto version : {MAT_FT_MAT5, MAT_FT_MAT73}) {
    INFO("version " << static_cast<int>(version));
    const fs::path path = scratch("dymola_rows") / "result.mat";
    {
      MatWriter w(path, version);
      w.text("Aclass", {"Atrajectory", "1.1", "", "binNormal"});
      w.text("name", kNames);
      w.numbers("dataInfo", 4, 4, kInfo);
      w.numbers("data_1", 2, 2, {0, 2, 2, 2});
      std::vector<double> d2;
      for (double t : kTimes) d2.insert(d2.end(), {t, 1 + t, 0});
      w.numbers("data_2", 5, 3, d2);
    }
    check_dymola(read_result_table(path.string()));
  }
  // binTrans, as Dymola and OpenModelica write .mat results (MATLAB v4): every matrix transposed.
  const fs::path path = scratch("dymola_columns") / "result.mat";
  {
    MatWriter w(path, MAT_FT_MAT4);
    w.text("Aclass", {"Atrajectory", "1.1", "", "binTrans"});
    w.text("name", as_columns(kNames));
    std::vector<double> info_t(16);
    for (std::size_t v = 0; v < 4; ++v)
      for (std::size_t k = 0; k < 4; ++k) info_t[k * 4 + v] = kInfo[v * 4 + k];
    w.numbers("dataInfo", 4, 4, info_t);
    w.numbers("data_1", 2, 2, {0, 2, 2, 2});
    std::vector<double> d2(3 * kTimes.size());
    for (std::size_t k = 0; k < kTimes.size(); ++k) {
      d2[0 * kTimes.size() + k] = kTimes[k];
      d2[1 * kTimes.size() + k] = 1 + kTimes[k];
    }
    w.numbers("data_2", 3, kTimes.size(), d2);
  }
  CHECK(is_mat_file(path.string()));
  check_dymola(read_result_table(path.string()));
}

TEST_CASE("mat files: what cannot be read is named", "[input][mat]") {
  const fs::path dir = scratch("errors");
  {
    MatWriter w(dir / "no_time.mat", MAT_FT_MAT5);
    w.numbers("t", 1, 2, {0, 1});
    w.numbers("y", 1, 2, {3, 4});
  }
  try {
    (void)read_result_table((dir / "no_time.mat").string());
    FAIL("no error");
  } catch (const InputFileError& e) {
    CHECK(std::string(e.what()).find("no_time.mat: error: no vector 'time'") != std::string::npos);
  }
  {
    MatWriter w(dir / "bad_info.mat", MAT_FT_MAT5);
    w.text("name", {"time", "x"});
    w.numbers("dataInfo", 2, 4, {0, 1, 0, -1, 2, 5, 0, -1});  // x in column 5 of a 2-column data_2
    w.numbers("data_1", 2, 1, {0, 1});
    w.numbers("data_2", 2, 2, {0, 1, 1, 2});
  }
  CHECK_THROWS_WITH(read_result_table((dir / "bad_info.mat").string()),
                    Catch::Contains("dataInfo of 'x' is out of range"));
  std::ofstream(dir / "text.csv") << "time,x\n0,1\n";
  CHECK_FALSE(is_mat_file((dir / "text.csv").string()));
  CHECK_FALSE(is_mat_file((dir / "missing.mat").string()));
}
