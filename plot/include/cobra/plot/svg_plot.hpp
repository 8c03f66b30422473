#pragma once
/// @file
/// Line charts as standalone SVG files, for the examples and the demo (the thesis' figures:
/// trajectories, tank energy, contact forces). No dependency: the SVG is written by hand.

#include <filesystem>
#include <string>
#include <vector>

namespace cobra::plot {

/// One line: points (x[i], y[i]); `label` appears in the legend.
struct Series {
  std::string label;
  std::vector<double> x;
  std::vector<double> y;
  bool dashed = false;
  /// Optional markers at these points (e.g. waypoints, where the phases of a task began), drawn
  /// on the line; `marker_labels[i]`, when given, is written beside marker i (e.g. "A", "B").
  std::vector<double> marker_x{};
  std::vector<double> marker_y{};
  std::vector<std::string> marker_labels{};
};

/// One panel: its axes fit all series (with a margin); titles and axis labels with units.
struct Panel {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<Series> series;
};

/// Panels stacked vertically, sharing the figure's width.
struct Figure {
  std::string title;
  std::vector<Panel> panels;
  int width = 900;          ///< px
  int panel_height = 260;   ///< px
};

/// The SVG text of `figure`. @throws std::invalid_argument naming the panel and series when a
/// series has x and y of different sizes or no points, a value is not finite, or it has more marker
/// labels than markers.
std::string toSvg(const Figure& figure);

/// `text` with <, >, & and " written as entities: safe in SVG or HTML text and attribute values.
std::string escapeXml(const std::string& text);

/// Writes toSvg(figure) to `path`. @throws std::runtime_error naming the file when it cannot.
void writeSvg(const Figure& figure, const std::filesystem::path& path);

/// "Nice" tick values covering [low, high]: about `target` of them, at 1, 2 or 5 × 10^k steps.
std::vector<double> niceTicks(double low, double high, int target = 6);

}  // namespace cobra::plot
