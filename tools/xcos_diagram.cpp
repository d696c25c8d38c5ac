#include "xcos_diagram.hpp"

#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>

#include <fmt/format.h>

#include "child_process.hpp"
#include "common.hpp"
#include "xcos_blocks.hpp"

namespace fs = std::filesystem;

namespace mo::tools {

extern const char* const xcos_script_text;  // xcos_script.sce, embedded by CMake

namespace {

/// Seconds without CPU use after which Scilab counts as hung (run_child).
constexpr double kScilabStallSeconds = 120.0;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string env(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

/// The user's _JAVA_OPTIONS with Java's temporary folder set to `tmp`: Scilab's
/// Java ignores TMPDIR and leaves its font files (+~JF*.tmp) in /tmp at every
/// run. _JAVA_OPTIONS is split at white space, so a folder with any keeps the
/// user's options as they are (and Java's files go to /tmp as before).
std::string java_options(const fs::path& tmp) {
  const std::string given = env("_JAVA_OPTIONS");
  const std::string folder = tmp.string();
  if (std::any_of(folder.begin(), folder.end(), [](unsigned char c) { return std::isspace(c); })) return given;
  return (given.empty() ? "" : given + " ") + "-Djava.io.tmpdir=" + folder;
}

/// The private work folder (mode 0700), removed on destruction unless released.
class WorkDir {
public:
  WorkDir() {
    std::string pattern = (fs::temp_directory_path() / "mocompile-xcos-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr)
      throw std::runtime_error("cannot create a temporary folder under " + fs::temp_directory_path().string());
    path_ = pattern;
  }
  ~WorkDir() {
    if (path_.empty()) return;
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  WorkDir(const WorkDir&) = delete;
  WorkDir& operator=(const WorkDir&) = delete;
  const fs::path& path() const { return path_; }
  fs::path release() { return std::exchange(path_, fs::path()); }

private:
  fs::path path_;
};

[[noreturn]] void fail(const std::string& diagram, const std::string& message) {
  throw DiagramError(diagram + ": error: " + message);
}

/// The scilab program: $MO_SCILAB, else `scilab` on PATH.
std::string scilab_program(const std::string& diagram) {
  const std::string given = env("MO_SCILAB");
  if (!given.empty()) {
    if (::access(given.c_str(), X_OK) != 0 || fs::is_directory(given))
      fail(diagram, "MO_SCILAB='" + given + "' is not an executable program (it names Scilab's `scilab` launcher)");
    return fs::absolute(given).string();
  }
  std::string found = find_on_path("scilab");
  if (found.empty())
    fail(diagram, "reading an Xcos diagram needs Scilab (6.1), which is not on PATH: install it "
                  "(Debian/Ubuntu: apt-get install scilab xvfb xauth) or set MO_SCILAB to the `scilab` program");
  return found;
}

/// The command line: xvfb-run -a scilab -nw -nb -f SCRIPT (or scilab alone on $DISPLAY).
std::vector<std::string> scilab_argv(const std::string& diagram, const fs::path& script) {
  std::vector<std::string> argv;
  const std::string scilab = scilab_program(diagram);
  const std::string xvfb = find_on_path("xvfb-run");
  if (!xvfb.empty()) {
    argv = {xvfb, "-a"};
  } else if (env("DISPLAY").empty()) {
    fail(diagram, "Scilab reads diagrams only with Java's graphics, and there is no display: install "
                  "xvfb-run (Debian/Ubuntu: apt-get install xvfb xauth) to run it without a window");
  }
  argv.insert(argv.end(), {scilab, "-nw", "-nb", "-f", script.string()});
  return argv;
}

/// --scilab-lib folders, then those of MO_SCILAB_LIBS (':'-separated), absolute.
std::vector<std::string> library_folders(const std::string& diagram, const DiagramOptions& options) {
  std::vector<std::string> all = options.libraries;
  const std::string listed = env("MO_SCILAB_LIBS");
  for (std::size_t start = 0; start < listed.size();) {
    const auto end = std::min(listed.find(':', start), listed.size());
    if (end > start) all.push_back(listed.substr(start, end - start));
    start = end + 1;
  }
  for (auto& folder : all) {
    if (!fs::is_directory(folder)) fail(diagram, "block library '" + folder + "' is not a folder");
    folder = fs::absolute(folder).lexically_normal().string();
    // libraries.txt has one folder a line; Scilab's translator puts the folders in a shell line.
    if (folder.find_first_of("\r\n\"'`$\\") != std::string::npos)
      fail(diagram, "block library folder '" + folder + "': names with line breaks, quotes, ` $ or \\ are not "
                    "supported (Scilab's translator puts them in a shell command)");
  }
  return all;
}

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

std::vector<std::string> read_lines(const fs::path& file) {
  std::vector<std::string> lines;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    lines.push_back(line);
  }
  return lines;
}

/// The last `n` lines of Scilab's output, without Java's class-path banner.
std::string log_tail(const fs::path& log, std::size_t n) {
  std::vector<std::string> kept;
  for (auto& line : read_lines(log))
    if (line.rfind("Picked up _JAVA_OPTIONS", 0) != 0 && !line.empty()) kept.push_back(line);
  std::string out;
  for (std::size_t i = kept.size() > n ? kept.size() - n : 0; i < kept.size(); ++i)
    out += "  | " + kept[i].substr(0, 400) + "\n";
  return out.empty() ? "  (nothing)\n" : out;
}

/// True when the log says that xvfb-run could not start its X server.
bool xvfb_failed(const fs::path& log) {
  for (const auto& line : read_lines(log))
    if (line.find("Xvfb failed to start") != std::string::npos) return true;
  return false;
}

/// The one file in `dir` whose name ends in `suffix`, or empty.
fs::path file_ending(const fs::path& dir, const std::string& suffix) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      return entry.path();
  }
  return {};
}

std::string joined(const std::vector<std::string>& names, std::size_t from) {
  std::string out;
  for (std::size_t i = from; i < names.size(); ++i) out += (i > from ? ", " : "") + names[i];
  return out;
}

/// Turns what Scilab left in `work` into an error message, or returns when it succeeded.
void check_outcome(const std::string& diagram, const fs::path& work, const ChildResult& run,
                   const DiagramOptions& options) {
  if (run.outcome == ChildOutcome::interrupted) fail(diagram, "interrupted; Scilab was stopped");
  const auto status = read_lines(work / "status.txt");
  const fs::path log = work / "scilab.log";
  if (status.empty()) {
    if (run.outcome == ChildOutcome::timed_out)
      fail(diagram, fmt::format("Scilab did not finish compiling the diagram within {:g} s and was stopped "
                                "(raise the limit with --scilab-timeout SECONDS); its output ends with:\n{}",
                                options.timeout_seconds, log_tail(log, 12)));
    if (run.outcome == ChildOutcome::stalled)
      fail(diagram, fmt::format("Scilab used no CPU for {:g} s, twice, and was stopped (a hang, often of its "
                                "Java at start-up); its output ends with:\n{}",
                                kScilabStallSeconds, log_tail(log, 12)));
    if (run.outcome == ChildOutcome::not_started)
      fail(diagram, "cannot run Scilab:\n" + log_tail(log, 12));
    fail(diagram, "Scilab stopped before compiling the diagram; its output ends with:\n" + log_tail(log, 12));
  }
  if (status[0] == "ok") return;
  if (status[0] == "missing-blocks")
    fail(diagram, "the diagram uses blocks that Scilab does not know: " + joined(status, 1) +
                      ". They come from a block library (e.g. Coselica): install it with Scilab's toolbox "
                      "manager (in Scilab: atomsInstall(\"coselica\")), or give the folder where it is with "
                      "--scilab-lib DIR (or MO_SCILAB_LIBS=DIR[:DIR...])");
  if (status[0] == "no-modelica")
    fail(diagram, "the diagram has no Modelica blocks: mocompile takes a diagram's Modelica part (blocks of "
                  "Scilab's Electrical, Thermo-hydraulics and Modelica palettes, or of Coselica), and this one "
                  "has none");
  if (status[0] == "unsafe-name") fail(diagram, joined(status, 1) + "; it is not compiled");
  std::string message = "Scilab could not compile the diagram: " + joined(status, 1) + "\n";
  for (const auto* name : {"S_translator.err"})
    if (fs::exists(work / "out" / name)) {
      std::ifstream in(work / "out" / name);
      std::stringstream text;
      text << in.rdbuf();
      if (!text.str().empty()) message += "  Scilab's Modelica translator said:\n" + text.str().substr(0, 4000);
    }
  fail(diagram, message + log_tail(log, 12));
}

/// Copies Scilab's Modelica files (not its logs) into `dir`.
void save_files(const fs::path& out, const std::string& dir) {
  fs::create_directories(dir);
  for (const auto& entry : fs::directory_iterator(out)) {
    const std::string name = entry.path().filename().string();
    if ((name.size() > 4 && (name.ends_with(".mo") || name.ends_with(".xml"))) || name == "translator_libs.txt")
      fs::copy_file(entry.path(), fs::path(dir) / name, fs::copy_options::overwrite_existing);
  }
}

}  // namespace

bool is_diagram_file(const std::string& path) {
  const std::string ext = lower(fs::path(path).extension().string());
  return ext == ".zcos" || ext == ".xcos";
}

ExtractedDiagram::ExtractedDiagram(fs::path work, fs::path flat, fs::path init, fs::path blocks)
    : work_(std::move(work)), flat_(std::move(flat)), init_(std::move(init)), blocks_(std::move(blocks)) {}

ExtractedDiagram::~ExtractedDiagram() {
  std::error_code ignored;
  fs::remove_all(work_, ignored);
}

std::unique_ptr<ExtractedDiagram> extract_flat_model(const std::string& diagram, const DiagramOptions& options) {
  const std::vector<std::string> libraries = library_folders(diagram, options);
  WorkDir work;
  const fs::path script = work.path() / "xcos_script.sce";
  const std::vector<std::string> argv = scilab_argv(diagram, script);
  const std::string copy = "diagram" + lower(fs::path(diagram).extension().string());
  fs::copy_file(diagram, work.path() / copy);
  write_text(script, xcos_script_text);
  std::string listed;
  for (const auto& folder : libraries) listed += folder + "\n";
  write_text(work.path() / "libraries.txt", listed);
  fs::create_directories(work.path() / "out");
  fs::create_directories(work.path() / "scilab-tmp");
  if (!options.quiet)
    std::cerr << options.tool << ": compiling " << diagram << " with Scilab (" << argv[argv.size() - 5]
              << "), which takes a while\n";
  ChildRun run;
  run.argv = argv;
  run.environment = {{"MO_XCOS_WORK", work.path().string()},
                     {"MO_XCOS_DIAGRAM", copy},
                     {"TMPDIR", (work.path() / "scilab-tmp").string()},
                     {"_JAVA_OPTIONS", java_options(work.path() / "scilab-tmp")},
                     {"MO_XCOS_MODE", options.blocks_only ? "blocks" : "flat"}};
  run.log_file = (work.path() / "scilab.log").string();
  run.done_file = (work.path() / "done").string();
  run.timeout_seconds = options.timeout_seconds;
  // Scilab's Java can hang at start-up waiting on a lock (seen on Debian 12
  // about once in 30 runs under load): no CPU used for this long is a hang.
  // (Under a shorter --scilab-timeout, the time limit alone.)
  run.stall_seconds = options.timeout_seconds > kScilabStallSeconds ? kScilabStallSeconds : 0.0;
  ChildResult result = run_child(run);
  // xvfb-run -a picks a free display number racily: when several start at
  // once one of them may find its display taken. Start again (twice at most),
  // and once after a hang.
  for (int retry = 0; retry < 2 && !fs::exists(work.path() / "status.txt") && xvfb_failed(run.log_file); ++retry)
    result = run_child(run);
  if (result.outcome == ChildOutcome::stalled) {
    if (!options.quiet)
      std::cerr << options.tool << ": Scilab used no CPU for " << run.stall_seconds
                << " s (hung at start-up?); starting it again\n";
    result = run_child(run);
  }
  check_outcome(diagram, work.path(), result, options);
  fs::path blocks = work.path() / "out" / "blocks.txt";
  if (!fs::exists(blocks)) blocks.clear();
  if (options.blocks_only) {
    if (blocks.empty()) fail(diagram, "Scilab reported success but did not list the diagram's blocks");
    return std::make_unique<ExtractedDiagram>(work.release(), fs::path(), fs::path(), blocks);
  }
  fs::path flat = file_ending(work.path() / "out", "_imf.mo");
  fs::path init = file_ending(work.path() / "out", "_imf_init.xml");
  if (flat.empty()) fail(diagram, "Scilab reported success but wrote no flat model (*_imf.mo)");
  if (!options.save_dir.empty()) {
    save_files(work.path() / "out", options.save_dir);
    flat = fs::path(options.save_dir) / flat.filename();
    if (!init.empty()) init = fs::path(options.save_dir) / init.filename();
  }
  return std::make_unique<ExtractedDiagram>(work.release(), flat, init, blocks);
}

std::vector<std::string> close_diagram_loop(ExtractedDiagram& diagram, const std::string& tool) {
  if (diagram.blocks_file().empty()) return {};
  XcosBlocks blocks;
  try {
    blocks = read_xcos_blocks(diagram.blocks_file());
  } catch (const std::runtime_error& e) {
    throw DiagramError(e.what());
  }
  std::ifstream in(diagram.flat_file(), std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  const ClosedLoop loop = close_xcos_loop(blocks, text.str());
  std::vector<std::string> lines;
  for (const auto& w : loop.warnings)
    lines.push_back(tool + ": warning: " + w + " (drive it with morun --input NAME=SPEC)");
  if (loop.closed.empty()) return lines;
  std::string closed;
  try {
    closed = with_closed_loop(text.str(), loop);
  } catch (const std::runtime_error& e) {
    lines.push_back(tool + ": warning: the diagram's blocks are not joined to its flat model: " + e.what() +
                    "; its inputs stay open (drive them with morun --input NAME=SPEC)");
    return lines;
  }
  fs::path file = diagram.flat_file();
  file.replace_filename(file.stem().string() + "_closed.mo");
  write_text(file, closed);
  diagram.set_flat_file(file);
  lines.insert(lines.begin(), fmt::format("{}: note: the diagram's non-Modelica blocks {} drive {} input{} of the "
                                          "Modelica part: translated to Modelica (docs/xcos-dialect.md)",
                                          tool, joined(loop.translated, 0), loop.closed.size(),
                                          loop.closed.size() == 1 ? "" : "s"));
  return lines;
}

std::string diagram_inputs_note(const frontend::flat::Model& model, const std::string& tool) {
  std::vector<std::string> names;
  for (const auto& v : model.variables)
    if (v.top_level_input) names.push_back("'" + v.name + "'");
  if (names.empty()) return {};
  return fmt::format("{}: note: the diagram's non-Modelica blocks drive the model through {} input{}: {} "
                     "(give {} a signal with morun --input NAME=SPEC)",
                     tool, names.size(), names.size() == 1 ? "" : "s", joined(names, 0),
                     names.size() == 1 ? "it" : "each");
}

}  // namespace mo::tools
