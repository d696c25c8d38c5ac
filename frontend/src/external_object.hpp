#pragma once
// An external object of one of ModelicaStandardTables' kinds: flattened once
// from its constructor call (flatten_external_objects.cpp), read by the
// expressions its functions become (flatten_tables.cpp).
#include "flattener.hpp"

#include <memory>
#include <string>
#include <vector>

namespace mo::frontend::detail {

struct Flattener::ExternalObject {
  enum class Kind { TimeTable, Table1D, Table2D };
  // The declaration, flattened at first use.
  ClassNode *cls = nullptr;
  Modifier mod;
  std::string name;
  SourceRange range;
  bool built = false;
  bool failed = false; ///< building it reported an error (once)
  // The table.
  Kind kind = Kind::TimeTable;
  int rows = 0, cols = 0;
  std::vector<ast::ExprPtr> table; ///< row-major, flat expressions
  std::vector<double> key;    ///< first column (2-D: of rows 2..), evaluated
  std::vector<double> key2;   ///< 2-D: first row (columns 2..), evaluated
  std::vector<int> columns;   ///< 1-based table columns of the outputs
  int smoothness = 1;         ///< Modelica.Blocks.Types.Smoothness: 1 linear, 2 Akima, 3 constant
  int extrapolation = 2;      ///< Extrapolation: 1 hold, 2 last two points, 3 periodic, 4 none
  double start_time = 0;
  ast::ExprPtr at(int r, int c) const { return table[static_cast<std::size_t>(r * cols + c)]->clone(); }
};

} // namespace mo::frontend::detail
