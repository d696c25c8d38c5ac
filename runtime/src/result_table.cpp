// Result files read as tables of signals; see read_result_table in input.hpp.
#include "mo/runtime/input.hpp"

#include "mat_reader.hpp"
#include "mo/runtime/mat_file.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace mo::runtime {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw InputFileError(path + ": error: " + what);
}

bool header(const std::string& line, NamedMatrix& m, std::string& type) {
  std::istringstream in(line);
  std::string decl;
  if (!(in >> type >> decl)) return false;
  if (type != "char" && type != "int" && type != "float" && type != "double") return false;
  m.is_char = type == "char";
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

/// The matrices of Dymola's textual format: `type name(rows,cols)` then its entries.
std::vector<NamedMatrix> read_matrices(std::istream& in, const std::string& path) {
  std::vector<NamedMatrix> out;
  std::string line, type;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    NamedMatrix m;
    if (line.empty() || line[0] == '#' || !header(line, m, type)) continue;
    if (m.is_char) {
      for (std::size_t r = 0; r < m.rows && std::getline(in, line); ++r) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        line.resize(m.cols, ' ');
        m.lines.push_back(line);
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

const NamedMatrix& find(const std::vector<NamedMatrix>& ms, const std::string& name, const std::string& path) {
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

const NamedMatrix* find_optional(const std::vector<NamedMatrix>& ms, const std::string& name) {
  for (const auto& m : ms)
    if (m.name == name) return &m;
  return nullptr;
}

/// Dymola's layout read in either orientation: one variable per row of `name`
/// and `dataInfo` (textual files, `binNormal`), or per column (`binTrans`, what
/// Dymola and OpenModelica write to .mat files; data_1/data_2 then hold one time
/// per column). The orientation is the shape of dataInfo (4 columns or 4 rows),
/// Aclass's fourth row deciding when both fit.
struct DymolaLayout {
  const NamedMatrix *names, *info, *d1, *d2;
  bool transposed = false;
  std::size_t variables() const { return transposed ? info->cols : info->rows; }
  std::string name(std::size_t v) const { return transposed ? names->column_text(v) : names->row_text(v); }
  double info_at(std::size_t v, std::size_t k) const {
    return transposed ? info->numbers[k * info->cols + v] : info->numbers[v * 4 + k];
  }
  static std::size_t times(const NamedMatrix& d, bool t) { return t ? d.cols : d.rows; }
  static std::size_t width(const NamedMatrix& d, bool t) { return t ? d.rows : d.cols; }
  static double at(const NamedMatrix& d, bool t, std::size_t time, std::size_t c) {
    return t ? d.numbers[c * d.cols + time] : d.numbers[time * d.cols + c];
  }
};

DymolaLayout dymola_layout(const std::vector<NamedMatrix>& ms, const std::string& path) {
  DymolaLayout l{&find(ms, "name", path), &find(ms, "dataInfo", path), &find(ms, "data_1", path),
                 &find(ms, "data_2", path)};
  if (!l.names->is_char || l.info->is_char || l.d1->is_char || l.d2->is_char)
    fail(path, "name must be a char matrix, dataInfo, data_1 and data_2 numeric");
  const bool normal = l.info->cols == 4 && l.names->rows == l.info->rows;
  const bool trans = l.info->rows == 4 && l.names->cols == l.info->cols;
  const NamedMatrix* aclass = find_optional(ms, "Aclass");
  const bool says_trans = aclass && aclass->is_char && aclass->rows >= 4 && aclass->row_text(3) == "binTrans";
  if (!normal && !trans) fail(path, "the shapes of name and dataInfo do not match (one variable per row or per column)");
  l.transposed = trans && (!normal || says_trans);
  return l;
}

InputTable dymola_table(const std::vector<NamedMatrix>& ms, const std::string& path) {
  const DymolaLayout l = dymola_layout(ms, path);
  const bool tr = l.transposed;
  const std::size_t n = DymolaLayout::times(*l.d2, tr);
  if (n == 0 || DymolaLayout::width(*l.d2, tr) == 0) fail(path, "data_2 is empty");
  if (DymolaLayout::times(*l.d1, tr) == 0 && DymolaLayout::width(*l.d1, tr) > 0) fail(path, "data_1 is empty");
  InputTable t;
  for (std::size_t r = 0; r < n; ++r) t.times.push_back(DymolaLayout::at(*l.d2, tr, r, 0));
  for (std::size_t v = 0; v < l.variables(); ++v) {
    const int set = static_cast<int>(l.info_at(v, 0));
    const long column = static_cast<long>(l.info_at(v, 1));
    if (set == 0 || column == 0) continue;  // time itself
    const NamedMatrix& data = set == 1 ? *l.d1 : *l.d2;
    const std::size_t c = static_cast<std::size_t>(std::labs(column)) - 1;
    if ((set != 1 && set != 2) || c >= DymolaLayout::width(data, tr))
      fail(path, "dataInfo of '" + l.name(v) + "' is out of range");
    const double sign = column < 0 ? -1.0 : 1.0;
    std::vector<double> values;
    for (std::size_t r = 0; r < n; ++r) values.push_back(sign * DymolaLayout::at(data, tr, set == 1 ? 0 : r, c));
    t.names.push_back(l.name(v));
    t.columns.push_back(std::move(values));
  }
  for (std::size_t k = 1; k < t.times.size(); ++k)
    if (t.times[k] < t.times[k - 1]) fail(path, "the time column of data_2 decreases");
  drop_repeated_times(t);
  return t;
}

/// A .mat file of plain vectors: the vector `time` and every numeric vector of its length as a column.
InputTable vector_table(const std::vector<NamedMatrix>& ms, const std::string& path) {
  const NamedMatrix* time = find_optional(ms, "time");
  if (!time || time->is_char || std::min(time->rows, time->cols) != 1)
    fail(path, "no vector 'time' (a .mat file is read in Dymola's layout, name/dataInfo/data_1/data_2, "
               "or as vectors beside a vector named time)");
  InputTable t;
  t.times = time->numbers;
  for (const auto& m : ms) {
    if (&m == time || m.is_char || std::min(m.rows, m.cols) != 1 || m.rows * m.cols != t.times.size()) continue;
    t.names.push_back(m.name);
    t.columns.push_back(m.numbers);
  }
  for (std::size_t k = 0; k < t.times.size(); ++k)
    if (!std::isfinite(t.times[k]) || (k > 0 && t.times[k] < t.times[k - 1]))
      fail(path, "the vector time is not finite and non-decreasing");
  if (t.times.empty()) fail(path, "the vector time is empty");
  drop_repeated_times(t);
  return t;
}

InputTable mat_table(const std::string& path) {
  const std::vector<NamedMatrix> ms = read_mat_matrices(path);
  if (find_optional(ms, "dataInfo")) return dymola_table(ms, path);
  return vector_table(ms, path);
}

}  // namespace

InputTable read_result_table(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the result file");
  std::string first;
  std::getline(in, first);
  if (!first.empty() && first.back() == '\r') first.pop_back();
  if (first == "#1") return dymola_table(read_matrices(in, path), path);
  in.close();
  if (looks_like_mat_file(path)) return mat_table(path);
  return read_input_csv(path);
}

bool is_mat_file(const std::string& path) { return looks_like_mat_file(path); }

}  // namespace mo::runtime
