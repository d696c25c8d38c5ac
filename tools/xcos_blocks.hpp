// A diagram's non-Modelica blocks in Modelica: the closed loop as one model.
//
// Scilab's compiler gathers the Modelica blocks of a diagram into one block
// whose inputs (`InPutPort<k>.vi` of the flat model) and outputs
// (`OutPutPort<k>.vo`) join the regular Scicos blocks. The Scilab script
// (tools/xcos_script.sce) lists those blocks and links, as the compiler's
// first pass (c_pass1) sees them, in `blocks.txt`:
//
//   mo-xcos-blocks 1
//   modelica M NIN NOUT          the Modelica block's number, its inputs, outputs
//   block K GUI SIM              a regular block (1..M-1): interface and computational function
//   in N v...  out N v...        port sizes (negative: inherited)
//   evtin N v  nzcross N v  nmode N v
//   rpar N v...  ipar N v...  opar N v...  firing N v...  state N v...  dstate N v...
//                                (N = -1: not a real matrix)
//   link F FP T TP               a data link, block F port FP to block T port TP
//   event F FP T TP              an activation link
//   end
//
// Each supported kind of block (docs/xcos-dialect.md, "The diagram's other
// blocks") becomes Modelica equations with its parameters from rpar/ipar/opar
// (numbers as read, never text of the diagram); an input of the Modelica part
// whose driving blocks are all supported is then defined by them, so the
// closed loop is one model. An input driven through a block that is not
// supported stays a free input (driven with morun --input), with a warning
// that names the block.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace mo::tools {

/// One regular block of the diagram, as listed by the Scilab script.
struct XcosBlock {
  int index = 0;            ///< 1-based, as in the links
  std::string gui;          ///< interface function (e.g. HYSTHERESIS), "?" when not a plain name
  std::string sim;          ///< computational function (e.g. hystheresis)
  std::map<std::string, std::vector<double>> fields;  ///< in, out, rpar, ipar, ...
  std::vector<std::string> not_real;                  ///< fields written as -1 (not a real matrix)
};

/// A link between ports: block `from` output `from_port` to block `to` input `to_port`.
struct XcosLink {
  int from = 0, from_port = 0, to = 0, to_port = 0;
};

/// The listing of blocks.txt.
struct XcosBlocks {
  int modelica = 0;  ///< the Modelica part's block number
  int inputs = 0;    ///< its inputs: InPutPort1..inputs
  int outputs = 0;   ///< its outputs: OutPutPort1..outputs
  std::vector<XcosBlock> blocks;
  std::vector<XcosLink> links, events;
};

/// Reads blocks.txt (untrusted: every token is checked, numbers parsed as
/// numbers). Throws std::runtime_error "FILE:LINE: error: ..." when malformed.
XcosBlocks read_xcos_blocks(const std::filesystem::path& file);

/// The loop closed through the supported blocks.
struct ClosedLoop {
  std::string declarations;             ///< Modelica declarations (one a line)
  std::string equations;                ///< Modelica equations (one or more a line)
  std::vector<int> closed;              ///< InPutPort numbers now defined by blocks
  std::vector<std::string> translated;  ///< "HYSTHERESIS (block 1)", ... in block order
  std::vector<std::string> warnings;    ///< why an input stays open, one a line
};

/// Translates the blocks that drive each input of the Modelica part. Only the
/// blocks reached backwards from an input matter (scopes, clocks, displays
/// and what feeds only them are ignored). `flat_text` is the flat model, to
/// check the port variables exist and to choose a prefix for the new names
/// that none of its names uses.
ClosedLoop close_xcos_loop(const XcosBlocks& blocks, const std::string& flat_text);

/// `flat_text` with the loop's declarations put before its `equation` line
/// and its equations before the class's final `end NAME;`. Throws
/// std::runtime_error when the text is not shaped as Xcos's flat files are.
std::string with_closed_loop(const std::string& flat_text, const ClosedLoop& loop);

}  // namespace mo::tools
