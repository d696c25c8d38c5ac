// Compiling generated sources into a shared object with the system C++
// compiler, cached by content, and loading it with dlopen.
//
//   key = hash(generated files, compiler, flags, include and link options,
//              runtime headers the code includes)
//   <cache>/<key>/model.so    reused while the key is unchanged
//
// The cache is safe against concurrent compilations of the same key: each
// compiles in its own temporary directory that is renamed into place.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "mo/codegen/generate.hpp"
#include "mo/runtime/model.hpp"

namespace mo::codegen {

/// How to compile generated code.
struct CompilerOptions {
  std::string compiler = "c++";  ///< looked up on PATH
  std::vector<std::string> flags{"-std=c++20", "-O1", "-fPIC", "-fvisibility=hidden"};
  std::vector<std::string> include_dirs;  ///< at least the runtime's include directory
  std::vector<std::string> link_flags;    ///< e.g. -L<dir> -lfoo; none for the runtime (see below)
  std::string cache_dir;  ///< empty: default_cache_dir()
  unsigned jobs = 1;      ///< translation units compiled in parallel
};

/// $XDG_CACHE_HOME/mocompile, else $HOME/.cache/mocompile, else /tmp/mocompile-cache.
std::string default_cache_dir();

/// Options that compile against this build's runtime headers (paths fixed
/// when mocompile was configured, or next to the installed executable). The
/// shared object is not linked against libmo_runtime: its runtime symbols
/// resolve when it is loaded, against the runtime of the loading process.
CompilerOptions runtime_compiler_options();

/// A compiled model on disk.
struct CompiledModel {
  std::string library;   ///< path of the shared object
  std::string key;       ///< cache key (hex)
  bool cached = false;   ///< true if it was already in the cache
  double seconds = 0.0;  ///< compile (and link) wall time; 0 if cached
};

/// The compiler failed; what() holds the command and the compiler's output.
class CompileError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// Compiles `sources` into a shared object in the cache, or finds it there.
/// Throws CompileError if the compiler fails, std::system_error on I/O errors.
CompiledModel compile_shared_object(const GeneratedSources& sources, const CompilerOptions& options);

/// Creates model instances from a loaded shared object. The library stays
/// loaded for the rest of the process (instances may outlive this object).
class LoadedModel {
public:
  /// dlopen()s `library` and finds `factory_symbol`. Throws std::runtime_error
  /// with dlerror()'s message on failure.
  LoadedModel(const std::string& library, const std::string& factory_symbol);
  /// A new instance.
  [[nodiscard]] std::unique_ptr<runtime::Model> create() const;

private:
  runtime::Model* (*factory_)() = nullptr;
};

}  // namespace mo::codegen
