// gnuplot figures; see plot.hpp.
#include "plot.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "common.hpp"
#include "mo/runtime/result.hpp"

namespace fs = std::filesystem;

namespace mo::tools {

namespace {

/// A gnuplot single-quoted string: quotes doubled, nothing else special.
std::string quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\n' || c == '\r') c = ' ';
    out += c == '\'' ? std::string("''") : std::string(1, c);
  }
  return out + "'";
}

/// Line colours in order (dark enough on white, distinct in grey print).
const char* const kPalette[] = {"#1f4e99", "#d95f02", "#7570b3", "#1b9e77", "#e7298a", "#66a61e", "#a6761d"};

/// `k`: the index of this curve among the panel's lines (for its colour).
std::string series_text(const Series& s, std::size_t k) {
  const std::string file = quote(s.file);
  const std::string y = s.y_expr.empty() ? std::to_string(s.y) : s.y_expr;
  const std::string title = " title " + quote(s.title);
  const std::string color = fmt::format(" lc rgb '{}'", kPalette[k % std::size(kPalette)]);
  switch (s.style) {
    case SeriesStyle::line:
      return fmt::format("{} using {}:{} with lines lw 2{}{}", file, s.x, y, color, title);
    case SeriesStyle::dotted:
      return fmt::format("{} using {}:{} with lines lw 2.5 dt 3{}{}", file, s.x, y, color, title);
    case SeriesStyle::points:
      return fmt::format("{} using {}:{} with points pt 7 ps 0.35 lc rgb '#555555'{}", file, s.x, y, title);
    case SeriesStyle::steps:
      return fmt::format("{} using {}:{} with steps lw 2{}{}", file, s.x, y, color, title);
    case SeriesStyle::band:
      return fmt::format("{} using {}:{}:{} with filledcurves fs transparent solid 0.35 noborder lc rgb '#f4a582'{}",
                         file, s.x, s.y, s.y_high, title);
  }
  return {};
}

/// The plot commands of every panel (shared by the PNG and the SVG pass).
std::string figure_body(const Figure& f) {
  std::ostringstream gp;
  gp << "set datafile separator ','\nset key outside right top\nset grid\nset lmargin 14\nset rmargin 30\n"
     << "set multiplot layout " << f.panels.size() << ",1 title " << quote(f.title) << "\n";
  for (std::size_t k = 0; k < f.panels.size(); ++k) {
    const Panel& p = f.panels[k];
    gp << "set ylabel " << quote(p.ylabel) << "\n";
    gp << (k + 1 == f.panels.size() ? "set xlabel " + quote(f.xlabel) : std::string("unset xlabel")) << "\n";
    gp << "$targets" << k << " << EOD\n";
    for (const auto& [t, v] : p.targets) gp << fmt::format("{:.17g},{:.17g}\n", t, v);
    gp << "EOD\n";
    std::string sep = "plot ";
    std::size_t lines = 0;
    for (const Series& s : p.series) {
      const bool is_line = s.style != SeriesStyle::points && s.style != SeriesStyle::band;
      gp << sep << series_text(s, is_line ? lines++ : 0);
      sep = ", \\\n  ";
    }
    for (std::size_t b = 0; b < p.bounds.size(); ++b) {
      gp << sep << fmt::format("{:.17g} with lines dt 2 lw 1.5 lc rgb '#2ca02c' {}", p.bounds[b],
                               b == 0 ? "title 'bound'" : "notitle");
      sep = ", \\\n  ";
    }
    if (!p.targets.empty())
      gp << sep << "$targets" << k << " using 1:2 with points pt 6 ps 2 lw 2 lc rgb '#d62728' title 'end-point target'";
    gp << "\n";
  }
  gp << "unset multiplot\n";
  return gp.str();
}

}  // namespace

std::string axis_label(const std::string& name, const std::string& unit) {
  return unit.empty() ? name : name + " [" + unit + "]";
}

std::string quotient_unit(const std::string& ua, const std::string& ub) {
  if (ub.empty()) return ua;
  const bool compound = ub.find_first_of("/.*") != std::string::npos;
  const std::string den = compound ? "(" + ub + ")" : ub;
  return (ua.empty() ? "1" : ua) + "/" + den;
}

std::vector<Panel> panels_by_unit(const std::string& file, const std::vector<PlotVariable>& variables,
                                  SeriesStyle style) {
  std::vector<Panel> panels;
  std::vector<std::vector<std::string>> names;  // per panel
  std::vector<std::string> units;               // per panel
  std::map<std::string, std::size_t> by_unit;
  for (const PlotVariable& v : variables) {
    std::size_t k = panels.size();
    if (!v.unit.empty()) k = by_unit.emplace(v.unit, panels.size()).first->second;
    if (k == panels.size()) {
      panels.emplace_back();
      names.emplace_back();
      units.push_back(v.unit);
    }
    panels[k].series.push_back({file, 1, v.column, 0, v.name, style, {}});
    names[k].push_back(v.name);
  }
  for (std::size_t k = 0; k < panels.size(); ++k) {
    std::string joined;
    for (std::size_t i = 0; i < names[k].size() && i < 3; ++i) joined += (i ? ", " : "") + names[k][i];
    if (names[k].size() > 3) joined += ", ...";
    panels[k].ylabel = axis_label(joined, units[k]);
  }
  return panels;
}

void render_figure(const Figure& figure, const std::string& dir, const std::string& stem) {
  if (figure.panels.empty()) return;
  const int height = figure.panel_height * static_cast<int>(figure.panels.size()) + 60;
  const std::string body = figure_body(figure);
  const fs::path base = fs::path(dir) / stem;
  const std::string script = base.string() + ".gp";
  runtime::write_file_atomic(script, [&](std::ostream& gp) {
    gp << "set terminal pngcairo noenhanced size " << figure.width << "," << height << " font 'sans,10'\n"
       << "set output " << quote(base.string() + ".png") << "\n"
       << body << "set terminal svg noenhanced size " << figure.width << "," << height
       << " font 'sans,11' background '#ffffff'\n"
       << "set output " << quote(base.string() + ".svg") << "\n"
       << body << "unset output\n";
  });
  run_gnuplot(script);
}

nlohmann::json unit_map(const runtime::ModelInfo& info) {
  nlohmann::json j = nlohmann::json::object();
  auto add = [&](const runtime::Variable& v) {
    if (!v.unit.empty()) j[v.name] = v.unit;
  };
  for (const auto& p : info.parameters) add(p);
  for (const auto& u : info.inputs) add(u);
  for (const auto& y : info.outputs) add(y);
  for (const auto& x : info.states) {
    if (!x.sensitivity) {
      add(x);
      continue;
    }
    const std::string unit = quotient_unit(info.states[x.sensitivity->state].unit,
                                           info.parameters[x.sensitivity->parameter].unit);
    if (!unit.empty()) j[x.name] = unit;
  }
  return j;
}

namespace {

/// Sets each variable's column to the one its name has in the header of
/// `csv` (gnuplot counts from 1, time is column 1) and drops the variables
/// the file does not hold.
std::vector<PlotVariable> columns_by_name(const std::string& csv, std::vector<PlotVariable> vars) {
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  std::map<std::string, std::size_t> column;
  std::size_t k = 1;
  for (std::size_t start = 0;; ++k) {
    const std::size_t end = header.find(',', start);
    column.emplace(header.substr(start, end == std::string::npos ? std::string::npos : end - start), k);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  std::vector<PlotVariable> out;
  for (auto& v : vars)
    if (const auto it = column.find(v.name); it != column.end()) {
      v.column = it->second;
      out.push_back(std::move(v));
    }
  return out;
}

}  // namespace

void plot_simulation(const std::string& dir, const runtime::ModelInfo& info, std::size_t declared_outputs) {
  const std::string csv = (fs::path(dir) / "result.csv").string();
  std::vector<PlotVariable> states, outputs, sensitivities;
  for (std::size_t i = 0; i < info.states.size(); ++i) {
    const auto& x = info.states[i];
    if (!x.sensitivity) {
      states.push_back({i + 2, x.name, x.unit});
      continue;
    }
    sensitivities.push_back({i + 2, x.name,
                             quotient_unit(info.states[x.sensitivity->state].unit,
                                           info.parameters[x.sensitivity->parameter].unit)});
  }
  for (std::size_t k = 0; k < info.outputs.size() && k < declared_outputs; ++k) {
    const auto& y = info.outputs[k];
    if (!y.name.starts_with("d(") && !y.name.starts_with("$"))
      outputs.push_back({info.states.size() + k + 2, y.name, y.unit});
  }
  constexpr std::size_t kMaxPanels = 12;  // a figure stays readable
  auto draw = [&](std::vector<PlotVariable> vars, const std::string& what, const std::string& stem) {
    Figure f;
    f.title = fmt::format("{}: {} (simulation)", info.name, what);
    f.panels = panels_by_unit(csv, columns_by_name(csv, std::move(vars)));
    if (f.panels.size() > kMaxPanels) {
      f.title += fmt::format(" - first {} of {} panels", kMaxPanels, f.panels.size());
      f.panels.resize(kMaxPanels);
    }
    render_figure(f, dir, stem);
  };
  draw(states, "states", "states");
  draw(outputs, "outputs", "outputs");
  draw(sensitivities, "state sensitivities", "sensitivities");
}

}  // namespace mo::tools
