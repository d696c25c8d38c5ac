// Printing a Program's sections as C++ (internal to codegen).
#pragma once

#include <string>
#include <vector>

#include "mo/codegen/generate.hpp"
#include "mo/codegen/program.hpp"

namespace mo::codegen::detail {

/// The right-hand side of `w[slot(e)] = ...` for an operator node `e`,
/// operands as w[slot] or constants; `cross` names the crossing override.
std::string node_code(const symbolic::ExprArena& arena, const Program& program,
                      const Instruction& ins);

/// The value of `e` as an operand: a constant literal or w[slot].
std::string operand_code(const symbolic::ExprArena& arena, const Program& program,
                         symbolic::Expr e);

/// The printed straight-line code and the functions that run sections.
struct PrintedSections {
  std::vector<std::string> parts;  ///< body of each <name>_part<K>.cpp (inside namespace detail)
  std::string declarations;        ///< declarations of the part functions
  std::string runners;             ///< block tables and section_<i>() functions, for model.cpp
  std::size_t instructions = 0;
};

/// Prints every section of `program`.
PrintedSections print_sections(const symbolic::ExprArena& arena, const Program& program,
                               const CodegenOptions& options);

/// The generated model class, the same text for every model: it reads the
/// tables and calls the section functions printed before it.
extern const char* const model_class;

}  // namespace mo::codegen::detail
