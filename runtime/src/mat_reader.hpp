// MATLAB .mat files (v4, v5, v7.3) read as named two-dimensional matrices, through matio.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace mo::runtime {

/// One two-dimensional matrix of a file: numbers or characters, row-major.
struct NamedMatrix {
  std::string name;
  std::size_t rows = 0, cols = 0;
  bool is_char = false;
  std::vector<double> numbers;  ///< numeric matrices: rows·cols entries, row-major
  std::vector<std::string> lines;  ///< char matrices: one string of `cols` characters per row
  /// Row r of a char matrix without trailing blanks and NULs.
  [[nodiscard]] std::string row_text(std::size_t r) const;
  /// Column c of a char matrix (read top to bottom) without trailing blanks and NULs.
  [[nodiscard]] std::string column_text(std::size_t c) const;
};

/// True if the file at `path` starts like a MATLAB file: the v5/v7.3 text header
/// `MATLAB` or a v4 header (a type word whose bytes are a valid v4 type code in
/// either byte order). Does not throw; false for files it cannot open.
bool looks_like_mat_file(const std::string& path);

/// Every real (double, single, integer, logical) or char matrix of rank ≤ 2 in
/// the file, in file order; cells, structs, sparse and complex matrices are
/// skipped. Throws InputFileError (`path: error: ...`) if matio cannot open it.
std::vector<NamedMatrix> read_mat_matrices(const std::string& path);

}  // namespace mo::runtime
