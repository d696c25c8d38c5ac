// MATLAB .mat files through matio; see mat_reader.hpp.
#include "mat_reader.hpp"

#include "mo/runtime/input.hpp"

#include <matio.h>

#include <array>
#include <cstdint>
#include <fstream>
#include <memory>

namespace mo::runtime {
namespace {

std::string trimmed(std::string s) {
  const auto end = s.find_last_not_of(std::string(" \0", 2));
  s.erase(end == std::string::npos ? 0 : end + 1);
  return s;
}

/// A v4 matrix header's type word MOPT: M byte order 0..4, O = 0, P data type 0..5, T 0..2.
bool v4_type(std::uint32_t v) {
  return v < 5000 && (v / 100) % 10 == 0 && (v / 10) % 10 <= 5 && v % 10 <= 2;
}

template <typename T>
double element(const void* data, std::size_t k) {
  return static_cast<double>(static_cast<const T*>(data)[k]);
}

/// Entry k (column-major) of a numeric matvar as a double.
double number_at(const matvar_t& v, std::size_t k) {
  switch (v.class_type) {
    case MAT_C_DOUBLE: return element<double>(v.data, k);
    case MAT_C_SINGLE: return element<float>(v.data, k);
    case MAT_C_INT8: return element<std::int8_t>(v.data, k);
    case MAT_C_UINT8: return element<std::uint8_t>(v.data, k);
    case MAT_C_INT16: return element<std::int16_t>(v.data, k);
    case MAT_C_UINT16: return element<std::uint16_t>(v.data, k);
    case MAT_C_INT32: return element<std::int32_t>(v.data, k);
    case MAT_C_UINT32: return element<std::uint32_t>(v.data, k);
    case MAT_C_INT64: return element<std::int64_t>(v.data, k);
    case MAT_C_UINT64: return element<std::uint64_t>(v.data, k);
    case MAT_C_EMPTY: case MAT_C_CELL: case MAT_C_STRUCT: case MAT_C_OBJECT: case MAT_C_CHAR:
    case MAT_C_SPARSE: case MAT_C_FUNCTION: case MAT_C_OPAQUE: break;
  }
  return 0.0;
}

/// Character k (column-major) of a char matvar; non-ASCII code units become '?'.
char char_at(const matvar_t& v, std::size_t k) {
  unsigned code = 0;
  switch (v.data_type) {
    case MAT_T_UINT16: case MAT_T_UTF16: code = static_cast<const std::uint16_t*>(v.data)[k]; break;
    case MAT_T_UINT32: case MAT_T_UTF32: code = static_cast<const std::uint32_t*>(v.data)[k]; break;
    case MAT_T_DOUBLE: code = static_cast<unsigned>(static_cast<const double*>(v.data)[k]); break;
    default: code = static_cast<const std::uint8_t*>(v.data)[k]; break;
  }
  return code < 128 ? static_cast<char>(code) : '?';
}

bool readable(const matvar_t& v) {
  if (v.rank > 2 || v.isComplex || v.data == nullptr) return false;
  switch (v.class_type) {
    case MAT_C_CHAR: case MAT_C_DOUBLE: case MAT_C_SINGLE: case MAT_C_INT8: case MAT_C_UINT8:
    case MAT_C_INT16: case MAT_C_UINT16: case MAT_C_INT32: case MAT_C_UINT32: case MAT_C_INT64:
    case MAT_C_UINT64: return true;
    case MAT_C_EMPTY: case MAT_C_CELL: case MAT_C_STRUCT: case MAT_C_OBJECT: case MAT_C_SPARSE:
    case MAT_C_FUNCTION: case MAT_C_OPAQUE: return false;
  }
  return false;
}

NamedMatrix convert(const matvar_t& v) {
  NamedMatrix m;
  m.name = v.name ? v.name : "";
  m.rows = v.rank >= 1 ? v.dims[0] : 1;
  m.cols = v.rank >= 2 ? v.dims[1] : 1;
  m.is_char = v.class_type == MAT_C_CHAR;
  if (m.is_char) {
    m.lines.assign(m.rows, std::string(m.cols, ' '));
    for (std::size_t c = 0; c < m.cols; ++c)
      for (std::size_t r = 0; r < m.rows; ++r) m.lines[r][c] = char_at(v, c * m.rows + r);
  } else {
    m.numbers.resize(m.rows * m.cols);
    for (std::size_t c = 0; c < m.cols; ++c)
      for (std::size_t r = 0; r < m.rows; ++r) m.numbers[r * m.cols + c] = number_at(v, c * m.rows + r);
  }
  return m;
}

void quiet_log(int, char*) {}

}  // namespace

std::string NamedMatrix::row_text(std::size_t r) const { return trimmed(lines.at(r)); }

std::string NamedMatrix::column_text(std::size_t c) const {
  std::string s;
  for (const auto& line : lines) s += c < line.size() ? line[c] : ' ';
  return trimmed(s);
}

bool looks_like_mat_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<unsigned char, 20> h{};
  if (!in.read(reinterpret_cast<char*>(h.data()), h.size())) return false;
  if (std::string(h.begin(), h.begin() + 6) == "MATLAB") return true;
  const std::uint32_t le = h[0] | h[1] << 8 | h[2] << 16 | static_cast<std::uint32_t>(h[3]) << 24;
  const std::uint32_t be = h[3] | h[2] << 8 | h[1] << 16 | static_cast<std::uint32_t>(h[0]) << 24;
  const std::uint32_t imag = h[12] | h[13] | h[14] | h[15];
  return (v4_type(le) || v4_type(be)) && imag <= 1 && (h[16] | h[17] | h[18] | h[19]) != 0;
}

std::vector<NamedMatrix> read_mat_matrices(const std::string& path) {
  Mat_LogInitFunc("mocompile", quiet_log);
  std::unique_ptr<mat_t, decltype(&Mat_Close)> file(Mat_Open(path.c_str(), MAT_ACC_RDONLY), &Mat_Close);
  if (!file) throw InputFileError(path + ": error: not a MATLAB .mat file matio can read (v4, v5 or v7.3)");
  std::vector<NamedMatrix> out;
  while (true) {
    std::unique_ptr<matvar_t, decltype(&Mat_VarFree)> v(Mat_VarReadNext(file.get()), &Mat_VarFree);
    if (!v) break;
    if (readable(*v)) out.push_back(convert(*v));
  }
  return out;
}

}  // namespace mo::runtime
