// C++ code generation: a lowered model (OdeModel) becomes one class deriving
// from mo::runtime::Model, printed from the instruction list of program.hpp.
//
//   <name>.hpp            typed header: sizes, named indices, create()
//   <name>_model.cpp      the class: info tables, sparsity, methods, factory
//   <name>_internal.hpp   declarations of the straight-line code functions
//   <name>_part<K>.cpp    the straight-line code, split so that no file holds
//                         more than options.instructions_per_file instructions
//
// The factory `extern "C" mo::runtime::Model* <name>_create()` lets a shared
// object be loaded with dlopen. Generated code needs the runtime headers and
// links against mo_runtime (block solvers) only.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "mo/symbolic/ode.hpp"

namespace mo::codegen {

/// Options of generate_cpp().
struct CodegenOptions {
  /// A C++ identifier: the namespace, the file names' stem and the factory
  /// symbol's prefix. Must satisfy is_cpp_identifier().
  std::string name = "mo_model";
  std::size_t instructions_per_function = 250;   ///< straight-line code per function
  std::size_t instructions_per_file = 10000;     ///< per translation unit (at least one function)
  /// If nonzero: exactly this many <name>_part<K>.cpp files (some may hold no
  /// code), instructions spread evenly; for build systems that must know the
  /// outputs in advance. Overrides instructions_per_file.
  std::size_t part_files = 0;
};

/// One generated file: a path relative to the output directory and its text.
struct GeneratedFile {
  std::string path;
  std::string text;
};

/// Everything generate_cpp() produced.
struct GeneratedSources {
  std::vector<GeneratedFile> files;  ///< headers and sources
  std::string factory_symbol;        ///< e.g. "mo_model_create"
  std::size_t instructions = 0;      ///< straight-line instructions printed
  std::size_t work_slots = 0;        ///< size of the work array

  /// The paths of the .cpp files.
  [[nodiscard]] std::vector<std::string> sources() const;
};

/// Generates the C++ of `model`. Adds derivative nodes to model.arena (its
/// meaning is unchanged). Throws std::invalid_argument for an invalid
/// options.name or a model code generation cannot handle (see lower_to_program).
GeneratedSources generate_cpp(symbolic::OdeModel& model, const CodegenOptions& options = {});

/// Writes the files into `directory` (created if needed), each atomically
/// (temporary file, then rename). Throws std::system_error on failure.
void write_sources(const GeneratedSources& sources, const std::string& directory);

}  // namespace mo::codegen
