// Figures drawn by gnuplot, each written as PNG and SVG.
//
//   Figure ─ Panel (one y axis, one unit) ─ Series (CSV columns: line, dotted,
//   points, steps, or a band between two columns), dashed bounds, marked
//   end-point targets.
//
// A figure has a title, an x label on its bottom panel, a y label with the
// unit on every panel and a legend. Names reach gnuplot only as single-quoted
// strings (never as markup), so model names cannot inject commands.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mo/runtime/model.hpp"

namespace mo::tools {

/// How a series is drawn.
enum class SeriesStyle {
  line,    ///< solid line
  dotted,  ///< dotted line (a re-simulation over a collocation solution)
  points,  ///< small filled circles (measurements)
  steps,   ///< piecewise constant (controls)
  band,    ///< shaded area between columns `y` and `y_high` (a confidence band)
};

/// One curve from a CSV file with a header line, columns counted from 1.
struct Series {
  std::string file;       ///< the CSV
  std::size_t x = 1;      ///< x column
  std::size_t y = 2;      ///< y column (the lower edge of a band)
  std::size_t y_high = 0; ///< band: the upper edge
  std::string title;      ///< legend entry
  SeriesStyle style = SeriesStyle::line;
  /// If set, a gnuplot expression used instead of column `y`, e.g.
  /// "($2 == 1 ? $5 : NaN)" (written by the tool, never from user text).
  std::string y_expr;
};

/// One y axis.
struct Panel {
  std::string ylabel;                ///< e.g. "x [m]" or "[rad]"
  std::vector<Series> series;        ///< drawn in order
  std::vector<double> bounds;        ///< horizontal dashed lines (green)
  /// End-point constraints: (t, value) marked with a red circle.
  std::vector<std::pair<double, double>> targets;
};

/// A figure of stacked panels sharing the x axis.
struct Figure {
  std::string title;                 ///< above the panels
  std::string xlabel = "time [s]";   ///< under the bottom panel
  std::vector<Panel> panels;
  int width = 900;                   ///< pixels
  int panel_height = 240;            ///< pixels per panel
};

/// Writes DIR/STEM.gp and, by gnuplot, DIR/STEM.png and DIR/STEM.svg. A
/// figure without panels writes nothing. Throws std::runtime_error if
/// gnuplot is missing or fails.
void render_figure(const Figure& figure, const std::string& dir, const std::string& stem);

/// "name [unit]", or just the name without a unit.
std::string axis_label(const std::string& name, const std::string& unit);

/// The unit of ∂a/∂b: "ua/ub", "ua", "1/ub" or "" (no units known).
std::string quotient_unit(const std::string& ua, const std::string& ub);

/// A variable to plot: its CSV column, legend name and unit.
struct PlotVariable {
  std::size_t column;
  std::string name;
  std::string unit;
};

/// Panels for `variables` from `file`, one per unit (in order of first
/// appearance; variables without a unit get a panel each), each with a line.
std::vector<Panel> panels_by_unit(const std::string& file, const std::vector<PlotVariable>& variables,
                                  SeriesStyle style = SeriesStyle::line);

/// {"name": "unit", ...} for every state, input, output and parameter with a
/// unit (sensitivities get the quotient unit), for summary.json and scripts.
nlohmann::json unit_map(const runtime::ModelInfo& info);

/// morun --plot for a simulation: DIR/states.{png,svg} (base states),
/// DIR/outputs.{png,svg} (the first `outputs` outputs: the declared ones, not
/// the variables added as columns) and, if present, DIR/sensitivities.{png,svg},
/// from DIR/result.csv, panels by unit. Columns are found by name in
/// result.csv's header; a variable it does not hold (--variables) is not drawn.
void plot_simulation(const std::string& dir, const runtime::ModelInfo& info,
                     std::size_t outputs = static_cast<std::size_t>(-1));

}  // namespace mo::tools
