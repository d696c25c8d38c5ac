// moreport: a Markdown report (as scripts/cart-pendulum-report.sh writes it)
// → one self-contained HTML file, figures inlined as SVG (see report_html.hpp).
//
// Exit status: 0 written, 1 written but a figure was missing (each named on
// stderr) or the files could not be read/written, 2 bad command line.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>

#include "mo/runtime/result.hpp"
#include "report_html.hpp"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  CLI::App app{"moreport — turn a Markdown report into one self-contained HTML page (figures\n"
               "inlined as SVG, no network), e.g. results/cart-pendulum/report.md → report.html."};
  app.set_version_flag("--version", "moreport 0.1.0");
  std::string input, output, title;
  app.add_option("report", input, "The Markdown report; figures are relative to its folder")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("-o,--output", output, "The HTML file (default: the report with .html)");
  app.add_option("--title", title, "Page title (default: the first heading)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (output.empty()) output = fs::path(input).replace_extension(".html").string();
  try {
    std::ifstream in(input);
    const std::string markdown{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    const auto report = mo::tools::markdown_to_html(markdown, fs::path(input).parent_path().string(), title);
    mo::runtime::write_file_atomic(output, [&](std::ostream& os) { os << report.html; });
    for (const auto& m : report.missing) std::cerr << "moreport: warning: missing figure " << m << "\n";
    std::cerr << "moreport: " << output << " (" << report.figures << " figures)\n";
    return report.missing.empty() ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "moreport: error: " << e.what() << "\n";
    return 1;
  }
}
