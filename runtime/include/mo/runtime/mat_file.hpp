// MATLAB .mat files as result tables (read_result_table in input.hpp reads them too).
#pragma once

#include <string>

namespace mo::runtime {

/// True if `path` is a MATLAB .mat file by its first bytes (the v5/v7.3 header
/// text `MATLAB`, or a valid v4 matrix header); false if it cannot be opened.
/// read_result_table reads such a file (v4, v5 or v7.3, through matio) either
/// in Dymola's result layout (name, dataInfo, data_1, data_2; one variable per
/// row, or per column as Dymola's and OpenModelica's `binTrans` files) or as
/// plain vectors: the vector `time` and every numeric vector of its length as a
/// column of that name.
bool is_mat_file(const std::string& path);

}  // namespace mo::runtime
