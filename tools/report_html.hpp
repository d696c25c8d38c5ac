// Markdown report → one self-contained HTML file.
//
// The subset the study reports use: `#` headings, paragraphs, `|` tables
// (the second row is the separator; `---:` right-aligns), fenced code blocks,
// lists (`- `), images on a line of their own (`![caption](fig.png)`) and, in
// text, `code`, **strong** and *emphasis*. Every character of the Markdown is
// HTML-escaped. A figure `F.png` is inlined as the SVG `F.svg` beside it (ids
// prefixed per figure so that figures do not collide), else as the PNG in a
// data: URI; nothing refers to the network.
#pragma once

#include <string>
#include <vector>

namespace mo::tools {

/// The HTML page and what was missing while making it.
struct HtmlReport {
  std::string html;                  ///< the complete document
  std::size_t figures = 0;           ///< figures inlined
  std::vector<std::string> missing;  ///< image paths that had neither .svg nor the file itself
};

/// Converts `markdown`; image paths are relative to `base_dir`. `title` is the
/// page title (the first heading if empty).
HtmlReport markdown_to_html(const std::string& markdown, const std::string& base_dir,
                            const std::string& title = {});

}  // namespace mo::tools
