// Markdown report → self-contained HTML; see report_html.hpp.
#include "report_html.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace mo::tools {

namespace {

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

/// Inline markup of one escaped-later text: `code`, **strong**, *em*.
std::string inline_html(const std::string& s) {
  std::string out;
  bool strong = false, em = false;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '`') {
      const auto end = s.find('`', i + 1);
      if (end != std::string::npos) {
        out += "<code>" + escape(s.substr(i + 1, end - i - 1)) + "</code>";
        i = end;
        continue;
      }
    }
    if (s.compare(i, 2, "**") == 0 && (strong || s.find("**", i + 2) != std::string::npos)) {
      out += strong ? "</strong>" : "<strong>";
      strong = !strong;
      ++i;
      continue;
    }
    const bool word_inside = i > 0 && i + 1 < s.size() && std::isalnum(static_cast<unsigned char>(s[i - 1])) &&
                             std::isalnum(static_cast<unsigned char>(s[i + 1]));
    if (s[i] == '*' && !word_inside && (em || s.find('*', i + 1) != std::string::npos)) {
      out += em ? "</em>" : "<em>";
      em = !em;
      continue;
    }
    out += escape(std::string(1, s[i]));
  }
  if (em) out += "</em>";
  if (strong) out += "</strong>";
  return out;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string base64(const std::string& bytes) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 | (unsigned char)bytes[i + 2];
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
  }
  if (i + 1 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16;
    out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8;
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
  }
  return out;
}

void replace_all(std::string& s, const std::string& from, const std::string& to) {
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
}

/// The <svg> element of an SVG file, its ids (and references to them) prefixed.
std::string inline_svg(std::string svg, const std::string& prefix) {
  const auto start = svg.find("<svg");
  if (start == std::string::npos) return {};
  svg.erase(0, start);
  std::vector<std::string> ids;
  for (const char* open : {"id='", "id=\""}) {
    const char close = open[3];
    for (std::size_t at = svg.find(open); at != std::string::npos; at = svg.find(open, at + 1)) {
      if (at > 0 && std::isalnum(static_cast<unsigned char>(svg[at - 1]))) continue;
      const auto end = svg.find(close, at + 4);
      if (end != std::string::npos) ids.push_back(svg.substr(at + 4, end - at - 4));
    }
  }
  for (const std::string& id : ids) {
    for (const char* q : {"'", "\""}) replace_all(svg, std::string("id=") + q + id + q, std::string("id=") + q + prefix + id + q);
    for (const char* tail : {"'", "\"", ")"}) replace_all(svg, "#" + id + tail, "#" + prefix + id + tail);
  }
  return svg;
}

/// `![caption](path)` alone on a line → (caption, path).
bool image_line(const std::string& line, std::string& caption, std::string& path) {
  if (!line.starts_with("![")) return false;
  const auto mid = line.find("](");
  if (mid == std::string::npos || line.back() != ')') return false;
  caption = line.substr(2, mid - 2);
  path = line.substr(mid + 2, line.size() - mid - 3);
  return true;
}

std::vector<std::string> table_cells(std::string line) {
  if (line.starts_with("|")) line.erase(0, 1);
  if (line.ends_with("|")) line.pop_back();
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, '|');) {
    const auto b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
    cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
  }
  return cells;
}

class Converter {
public:
  Converter(const std::string& base_dir) : base_(base_dir) {}

  HtmlReport run(const std::string& markdown, std::string title) {
    std::vector<std::string> lines;
    std::stringstream in(markdown);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    std::ostringstream body;
    for (std::size_t i = 0; i < lines.size();) i = block(lines, i, body, title);
    out_.html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
                escape(title) + "</title>\n<style>\n" + style() + "</style>\n</head>\n<body>\n<main>\n" +
                body.str() + "</main>\n</body>\n</html>\n";
    return std::move(out_);
  }

private:
  static std::string style() {
    return "body{font-family:system-ui,sans-serif;line-height:1.45;margin:0;color:#1b1b1b;background:#fff}\n"
           "main{max-width:1000px;margin:0 auto;padding:1em 1.5em}\n"
           "table{border-collapse:collapse;margin:1em 0;font-size:.92em}\n"
           "th,td{border:1px solid #ccc;padding:.25em .5em}th{background:#f3f3f3}\n"
           "td.r,th.r{text-align:right}pre{background:#f6f6f6;padding:.6em;overflow-x:auto}\n"
           "code{font-size:.92em}figure{margin:1.2em 0}figure svg,figure img{max-width:100%;height:auto}\n"
           "figcaption{font-size:.9em;color:#444}\n";
  }

  std::size_t block(const std::vector<std::string>& lines, std::size_t i, std::ostringstream& os,
                    std::string& title) {
    const std::string& line = lines[i];
    if (line.empty()) return i + 1;
    if (line.starts_with("```")) {
      os << "<pre><code>";
      ++i;
      for (; i < lines.size() && !lines[i].starts_with("```"); ++i) os << escape(lines[i]) << "\n";
      os << "</code></pre>\n";
      return i + 1;
    }
    if (line.starts_with("#")) {
      const auto level = std::min<std::size_t>(line.find_first_not_of('#'), 6);
      const std::string text = line.substr(line.find_first_not_of("# "));
      if (title.empty()) title = text;
      os << "<h" << level << ">" << inline_html(text) << "</h" << level << ">\n";
      return i + 1;
    }
    std::string caption, path;
    if (image_line(line, caption, path)) {
      figure(caption, path, os);
      return i + 1;
    }
    if (line.starts_with("|")) return table(lines, i, os);
    if (line.starts_with("- ")) {
      os << "<ul>\n";
      for (; i < lines.size() && lines[i].starts_with("- "); ++i)
        os << "<li>" << inline_html(lines[i].substr(2)) << "</li>\n";
      os << "</ul>\n";
      return i;
    }
    std::string text;
    for (; i < lines.size() && !lines[i].empty() && !lines[i].starts_with("#") && !lines[i].starts_with("|") &&
           !lines[i].starts_with("```") && !lines[i].starts_with("![");
         ++i)
      text += (text.empty() ? "" : "\n") + lines[i];
    os << "<p>" << inline_html(text) << "</p>\n";
    return i;
  }

  std::size_t table(const std::vector<std::string>& lines, std::size_t i, std::ostringstream& os) {
    const auto header = table_cells(lines[i++]);
    std::vector<bool> right;
    if (i < lines.size() && lines[i].starts_with("|"))
      for (const auto& c : table_cells(lines[i++])) right.push_back(c.ends_with(":"));
    auto cls = [&](std::size_t k) { return k < right.size() && right[k] ? " class=\"r\"" : ""; };
    os << "<table>\n<thead><tr>";
    for (std::size_t k = 0; k < header.size(); ++k) os << "<th" << cls(k) << ">" << inline_html(header[k]) << "</th>";
    os << "</tr></thead>\n<tbody>\n";
    for (; i < lines.size() && lines[i].starts_with("|"); ++i) {
      const auto cells = table_cells(lines[i]);
      os << "<tr>";
      for (std::size_t k = 0; k < cells.size(); ++k) os << "<td" << cls(k) << ">" << inline_html(cells[k]) << "</td>";
      os << "</tr>\n";
    }
    os << "</tbody>\n</table>\n";
    return i;
  }

  void figure(const std::string& caption, const std::string& path, std::ostringstream& os) {
    const fs::path file = fs::path(base_) / path;
    fs::path svg = file;
    svg.replace_extension(".svg");
    std::error_code ec;
    std::string content;
    if (fs::exists(svg, ec)) {
      content = inline_svg(slurp(svg), "f" + std::to_string(out_.figures + 1) + "_");
    } else if (fs::exists(file, ec) && file.extension() == ".png") {
      content = "<img alt=\"" + escape(caption) + "\" src=\"data:image/png;base64," + base64(slurp(file)) + "\">";
    }
    if (content.empty()) {
      out_.missing.push_back(path);
      os << "<p><em>missing figure: " << escape(path) << "</em></p>\n";
      return;
    }
    ++out_.figures;
    os << "<figure>\n" << content << "\n<figcaption>" << inline_html(caption) << "</figcaption>\n</figure>\n";
  }

  std::string base_;
  HtmlReport out_;
};

}  // namespace

HtmlReport markdown_to_html(const std::string& markdown, const std::string& base_dir, const std::string& title) {
  return Converter(base_dir).run(markdown, title);
}

}  // namespace mo::tools
