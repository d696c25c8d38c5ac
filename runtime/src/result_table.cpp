// Result files read as tables of signals; see read_result_table in input.hpp.
#include "mo/runtime/input.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

namespace mo::runtime {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw InputFileError(path + ": error: " + what);
}

/// One matrix of Dymola's textual format: `type name(rows,cols)` then its entries.
struct TextMatrix {
  std::string type, name;
  std::size_t rows = 0, cols = 0;
  std::vector<std::string> lines;   ///< char matrices: one line per row
  std::vector<double> numbers;      ///< numeric matrices: row-major
};

bool header(const std::string& line, TextMatrix& m) {
  std::istringstream in(line);
  std::string decl;
  if (!(in >> m.type >> decl)) return false;
  if (m.type != "char" && m.type != "int" && m.type != "float" && m.type != "double") return false;
  const auto open = decl.find('('), comma = decl.find(','), close = decl.find(')');
  if (open == std::string::npos || comma == std::string::npos || close == std::string::npos) return false;
  m.name = decl.substr(0, open);
  try {
    m.rows = std::stoul(decl.substr(open + 1, comma - open - 1));
    m.cols = std::stoul(decl.substr(comma + 1, close - comma - 1));
  } catch (const std::exception&) {
    return false;
  }
  return m.rows < (1u << 24) && m.cols < (1u << 24);
}

std::vector<TextMatrix> read_matrices(std::istream& in, const std::string& path) {
  std::vector<TextMatrix> out;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    TextMatrix m;
    if (line.empty() || line[0] == '#' || !header(line, m)) continue;
    if (m.type == "char") {
      for (std::size_t r = 0; r < m.rows && std::getline(in, line); ++r) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        m.lines.push_back(line.substr(0, line.find_last_not_of(' ') + 1));
      }
      if (m.lines.size() != m.rows) fail(path, "matrix " + m.name + " ends early");
    } else {
      const std::size_t n = m.rows * m.cols;
      m.numbers.reserve(n);
      while (m.numbers.size() < n && std::getline(in, line)) {
        std::istringstream fields(line.substr(0, line.find('#')));
        for (std::string f; fields >> f && m.numbers.size() < n;) {
          char* end = nullptr;
          const double v = std::strtod(f.c_str(), &end);
          if (end == f.c_str() || *end != '\0') fail(path, "matrix " + m.name + ": '" + f + "' is not a number");
          m.numbers.push_back(v);
        }
      }
      if (m.numbers.size() != n) fail(path, "matrix " + m.name + " ends early");
    }
    out.push_back(std::move(m));
  }
  return out;
}

const TextMatrix& find(const std::vector<TextMatrix>& ms, const std::string& name, const std::string& path) {
  for (const auto& m : ms)
    if (m.name == name) return m;
  fail(path, "no matrix '" + name + "' (not a Dymola textual result)");
}

/// Keeps the first and the last row of a time given more than twice.
void drop_repeated_times(InputTable& t) {
  std::vector<std::size_t> keep;
  for (std::size_t k = 0; k < t.times.size(); ++k) {
    const bool middle = k > 0 && k + 1 < t.times.size() && t.times[k - 1] == t.times[k] &&
                        t.times[k + 1] == t.times[k];
    if (!middle) keep.push_back(k);
  }
  if (keep.size() == t.times.size()) return;
  InputTable out{t.names, {}, std::vector<std::vector<double>>(t.columns.size())};
  for (std::size_t k : keep) {
    out.times.push_back(t.times[k]);
    for (std::size_t j = 0; j < t.columns.size(); ++j) out.columns[j].push_back(t.columns[j][k]);
  }
  t = std::move(out);
}

InputTable dymola_table(std::istream& in, const std::string& path) {
  const std::vector<TextMatrix> ms = read_matrices(in, path);
  const TextMatrix& names = find(ms, "name", path);
  const TextMatrix& info = find(ms, "dataInfo", path);
  const TextMatrix& d1 = find(ms, "data_1", path);
  const TextMatrix& d2 = find(ms, "data_2", path);
  // Dymola stores name and dataInfo either one variable per row or transposed.
  const bool by_row = info.cols == 4 && names.rows == info.rows;
  if (!by_row) fail(path, "name and dataInfo must list one variable per row (transposed files are not read)");
  if (d2.cols == 0 || d2.rows == 0) fail(path, "data_2 is empty");
  InputTable t;
  for (std::size_t r = 0; r < d2.rows; ++r) t.times.push_back(d2.numbers[r * d2.cols]);
  for (std::size_t v = 0; v < names.rows; ++v) {
    const int set = static_cast<int>(info.numbers[v * 4]);
    const long column = static_cast<long>(info.numbers[v * 4 + 1]);
    if (set == 0 || column == 0) continue;  // time itself
    const TextMatrix& data = set == 1 ? d1 : d2;
    const std::size_t c = static_cast<std::size_t>(std::labs(column)) - 1;
    if ((set != 1 && set != 2) || c >= data.cols) fail(path, "dataInfo of '" + names.lines[v] + "' is out of range");
    const double sign = column < 0 ? -1.0 : 1.0;
    std::vector<double> values;
    for (std::size_t r = 0; r < d2.rows; ++r)
      values.push_back(sign * (set == 1 ? data.numbers[c] : data.numbers[r * data.cols + c]));
    t.names.push_back(names.lines[v]);
    t.columns.push_back(std::move(values));
  }
  for (std::size_t k = 1; k < t.times.size(); ++k)
    if (t.times[k] < t.times[k - 1]) fail(path, "the time column of data_2 decreases");
  drop_repeated_times(t);
  return t;
}

}  // namespace

InputTable read_result_table(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the result file");
  std::string first;
  std::getline(in, first);
  if (!first.empty() && first.back() == '\r') first.pop_back();
  if (first == "#1") return dymola_table(in, path);
  if (first.starts_with("MATLAB") || first.find('\0') != std::string::npos)
    fail(path, "a binary .mat result is not read; give a CSV result or Dymola's textual format");
  return read_input_csv(path);
}

}  // namespace mo::runtime
