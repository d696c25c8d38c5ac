// MATLAB .mat files as study inputs: an estimation's measurements and its
// input signal from a v5 file of plain vectors (written here with matio from a
// simulation), and the initial guess (init_result) from a Dymola-layout v4
// result stored per column (binTrans), as Dymola and OpenModelica write them.
#include <matio.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <sstream>

#include "e2e/cli.hpp"
#include "e2e/support.hpp"

using namespace mo::e2e;
using nlohmann::json;

namespace {

/// Writes `columns` (name → values) to a .mat file of `version` as column vectors.
void write_vectors(const fs::path& path, mat_ft version,
                   const std::vector<std::pair<std::string, std::vector<double>>>& columns) {
  mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, version);
  REQUIRE(mat != nullptr);
  for (const auto& [name, values] : columns) {
    std::vector<double> data = values;
    std::size_t dims[2] = {data.size(), 1};
    matvar_t* v = Mat_VarCreate(name.c_str(), MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, data.data(), 0);
    REQUIRE(v != nullptr);
    CHECK(Mat_VarWrite(mat, v, MAT_COMPRESSION_NONE) == 0);
    Mat_VarFree(v);
  }
  Mat_Close(mat);
}

/// The columns of a CSV file with a header line.
std::vector<std::pair<std::string, std::vector<double>>> csv_columns(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::pair<std::string, std::vector<double>>> out;
  std::getline(in, line);
  std::stringstream header(line);
  for (std::string name; std::getline(header, name, ',');) out.push_back({name, {}});
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string field;
    for (std::size_t c = 0; std::getline(row, field, ',') && c < out.size(); ++c)
      out[c].second.push_back(std::stod(field));
  }
  return out;
}

json summary(const fs::path& dir) { return json::parse(slurp(dir / "summary.json")); }

}  // namespace

TEST_CASE("mat data: an estimation reads its measurements and its input from a .mat file", "[e2e][mat]") {
  const fs::path dir = scratch("mat_estimation");
  Run r = morun(quoted(kData + "Decay.mo") + " -c Decay --stop-time 2 --intervals 40 --rtol 1e-10 "
                "--atol 1e-12 --input u=const:0.5 --measure x,a -o " + quoted((dir / "sim").string()),
                dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  auto columns = csv_columns(dir / "sim" / "measurements.csv");
  REQUIRE(columns.size() == 3);
  const std::size_t n = columns[0].second.size();
  columns.push_back({"u", std::vector<double>(n, 0.5)});        // the input signal, read by csv:
  columns.push_back({"junk", std::vector<double>(n, 1e9)});     // not named by outputs: ignored
  write_vectors(dir / "data.mat", MAT_FT_MAT5, columns);
  const fs::path out = dir / "est";
  const std::string base = quoted(kData + "DecayDesign.mop") + " -L " + quoted(kData + "Decay.mo") +
                           " -c DecayEstimate --option " + quoted("data={\"" + (dir / "data.mat").string() + "\"}") +
                           " --option " + quoted("inputs={\"u=csv:" + (dir / "data.mat").string() + "\"}");
  r = morun(base + " --option 'outputs={x,a}' -o " + quoted(out.string()), dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const json e = summary(out)["estimates"][0];
  CHECK(e["name"] == "k");
  CHECK(e["estimate"].get<double>() == Approx(2.0).epsilon(1e-3));  // noise-free data
  // Without outputs the file's measured vectors are unknown: a diagnostic, not a guess.
  r = morun(base + " -o " + quoted((dir / "bad").string()), dir);
  CHECK(r.status != 0);
  CHECK(r.err.find("needs study option 'outputs'") != std::string::npos);
  // A name of outputs that the file lacks is named.
  r = morun(base + " --option 'outputs={x,b}' -o " + quoted((dir / "bad2").string()), dir);
  CHECK(r.status != 0);
  CHECK(r.err.find("no vector or variable 'b'") != std::string::npos);
}

TEST_CASE("mat data: init_result from a Dymola-layout .mat result stored per column", "[e2e][mat]") {
  const fs::path dir = scratch("mat_init_result");
  const fs::path path = dir / "guess.mat";
  {
    // binTrans: name(maxlen, nvar), dataInfo(4, nvar), data_2(nvar2, ntimes); x2 a negated alias.
    mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, MAT_FT_MAT4);
    REQUIRE(mat != nullptr);
    auto write = [&](const char* name, matio_classes cls, matio_types type, std::size_t rows, std::size_t cols,
                     void* data) {
      std::size_t dims[2] = {rows, cols};
      matvar_t* v = Mat_VarCreate(name, cls, type, 2, dims, data, 0);
      REQUIRE(v != nullptr);
      CHECK(Mat_VarWrite(mat, v, MAT_COMPRESSION_NONE) == 0);
      Mat_VarFree(v);
    };
    const std::vector<std::string> names = {"time", "x1", "x2"};
    std::vector<char> name(4 * 3, ' ');  // column-major: column v is names[v]
    for (std::size_t v = 0; v < 3; ++v)
      for (std::size_t c = 0; c < names[v].size(); ++c) name[v * 4 + c] = names[v][c];
    write("name", MAT_C_CHAR, MAT_T_UINT8, 4, 3, name.data());
    std::vector<double> info = {0, 1, 0, -1, 2, 2, 0, -1, 2, -3, 0, -1};  // column-major 4×3
    write("dataInfo", MAT_C_DOUBLE, MAT_T_DOUBLE, 4, 3, info.data());
    std::vector<double> d1 = {0, 0};
    write("data_1", MAT_C_DOUBLE, MAT_T_DOUBLE, 1, 2, d1.data());
    std::vector<double> d2;  // column-major 3×9: one column per time
    for (int k = 0; k <= 8; ++k) {
      const double t = 0.5 * k;
      d2.insert(d2.end(), {t, 7 + t, 1 + t / 2});
    }
    write("data_2", MAT_C_DOUBLE, MAT_T_DOUBLE, 3, 9, d2.data());
    Mat_Close(mat);
  }
  const fs::path out = dir / "run";
  // max_iter = 0 returns the initial guess itself.
  const Run r = morun(quoted(kData + "loops/Blocks.mop") + " -o " + quoted(out.string()) +
                          " --option plot=false --option max_iter=0 --option 'init_result=\"" + path.string() + "\"'",
                      dir);
  INFO(r.err);
  REQUIRE(fs::exists(out / "trajectories.csv"));
  const auto columns = csv_columns(out / "trajectories.csv");
  std::size_t t = 0, x1 = 0, x2 = 0;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (columns[c].first == "time") t = c;
    if (columns[c].first == "x1") x1 = c;
    if (columns[c].first == "x2") x2 = c;
  }
  REQUIRE((x1 > 0 && x2 > 0));
  for (std::size_t k = 0; k < columns[t].second.size(); ++k) {
    const double time = columns[t].second[k];
    CHECK(columns[x1].second[k] == Approx(7 + time).margin(1e-9));
    CHECK(columns[x2].second[k] == Approx(-(1 + time / 2)).margin(1e-9));
  }
}
