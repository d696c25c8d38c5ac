// Diagrams in: an Xcos diagram (.zcos, .xcos) → the flat Modelica model that
// Scilab's translator writes for it, by running Scilab without a window the
// way Xcos compiles a diagram (tools/xcos_script.sce). mocompile and morun
// then go on with that flat file as with any .mo.
//
// Scilab is the program named by MO_SCILAB, else `scilab` on PATH; it runs
// under `xvfb-run` (or on $DISPLAY when xvfb-run is missing) with an argument
// vector, in a private temporary folder that is removed afterwards, with a
// time limit. Block libraries (Coselica) come from --scilab-lib folders,
// MO_SCILAB_LIBS (':'-separated) and the toolboxes installed with Scilab's
// toolbox manager (ATOMS).
#pragma once

#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "mo/frontend/flat.hpp"

namespace mo::tools {

/// True for a file name ending in .zcos or .xcos (any case).
bool is_diagram_file(const std::string& path);

/// How to run Scilab on a diagram.
struct DiagramOptions {
  std::vector<std::string> libraries;  ///< --scilab-lib folders (before MO_SCILAB_LIBS)
  double timeout_seconds = 600.0;      ///< --scilab-timeout
  std::string save_dir;                ///< --save-flat: also copy Scilab's files here
  std::string tool = "mocompile";      ///< prefix of progress lines
  bool quiet = false;                  ///< no progress line
  bool init_fixed = false;             ///< --init-fixed: apply the init file's fixed flags (xcos_init.hpp)
  bool open_loop = false;              ///< --open-loop: leave the non-Modelica blocks out (xcos_blocks.hpp)
  bool blocks_only = false;            ///< list the blocks only (no flat model; block libraries may be missing)
};

/// Why a diagram gave no flat model; the message is complete (it starts with
/// "<diagram>: error: " and says what to install or change). Exit status 1.
struct DiagramError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Scilab's files for one diagram; the temporary folder goes with it.
class ExtractedDiagram {
public:
  ExtractedDiagram(std::filesystem::path work, std::filesystem::path flat, std::filesystem::path init,
                   std::filesystem::path blocks = {});
  ~ExtractedDiagram();
  ExtractedDiagram(const ExtractedDiagram&) = delete;
  ExtractedDiagram& operator=(const ExtractedDiagram&) = delete;

  /// `<title>_imf.mo`: the flat model (in the --save-flat folder when given).
  const std::filesystem::path& flat_file() const { return flat_; }
  /// `<title>_imf_init.xml` (fixed flags, start and nominal values), or empty.
  const std::filesystem::path& init_file() const { return init_; }
  /// The diagram's regular blocks and links (xcos_blocks.hpp), or empty.
  const std::filesystem::path& blocks_file() const { return blocks_; }
  /// The private work folder (removed with this object).
  const std::filesystem::path& work_dir() const { return work_; }
  /// Replaces the flat model (by the closed loop's).
  void set_flat_file(std::filesystem::path flat) { flat_ = std::move(flat); }

private:
  std::filesystem::path work_, flat_, init_, blocks_;
};

/// Runs Scilab on `diagram` and returns its flat model. Throws DiagramError
/// when Scilab (or xvfb-run) is missing, a block library the diagram uses is
/// not installed, Scilab fails, or it does not finish in time.
std::unique_ptr<ExtractedDiagram> extract_flat_model(const std::string& diagram, const DiagramOptions& options);

/// Joins the diagram's supported non-Modelica blocks to the flat model
/// (xcos_blocks.hpp): writes `<title>_imf_closed.mo` (same class) beside the
/// flat file and makes it the diagram's flat file. Returns the lines for
/// stderr: which blocks were translated, and a warning for each input that
/// stays open (all of them when the flat file is not shaped as Xcos writes
/// it). Does nothing without a block list. Throws DiagramError when the
/// block list is malformed.
std::vector<std::string> close_diagram_loop(ExtractedDiagram& diagram, const std::string& tool);

/// One line naming the inputs of `model` that the diagram's non-Modelica
/// blocks drive (free inputs), or empty when there are none.
std::string diagram_inputs_note(const frontend::flat::Model& model, const std::string& tool);

}  // namespace mo::tools
