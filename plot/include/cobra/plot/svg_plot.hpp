#pragma once
/// @file
/// Line charts as standalone SVG files, for the examples and the demo (the thesis' figures:
/// trajectories, tank energy, contact forces). No dependency: the SVG is written by hand.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace cobra::plot {

/// One line: points (x[i], y[i]); `label` appears in the legend (below the panel, shortened in
/// its middle when wider than the panel). Each series of a panel gets its own colour, dash pattern
/// and marker shape (markers spread along the line, staggered per series), so lines that coincide
/// stay visible and the figure reads in grey too.
struct Series {
  std::string label;
  std::vector<double> x;
  std::vector<double> y;
  bool dashed = false;  ///< a reference (a threshold, a nominal path): dashed '6,4', no markers
  /// Optional markers at these points (e.g. waypoints, where the phases of a task began), drawn
  /// on the line; `marker_labels[i]`, when given, is written beside marker i (e.g. "A", "B").
  std::vector<double> marker_x{};
  std::vector<double> marker_y{};
  std::vector<std::string> marker_labels{};
};

/// How a panel scales its axes: Equal gives x and y the same metres per pixel (a path in a plane
/// keeps its shape); Auto is Equal when both axis labels end in the same length unit ("[m]",
/// "[mm]" or "[cm]": x and y are positions), else Free (each axis fits its own range). An Equal
/// panel whose path is taller than wide gets a taller plot (up to 2.5 times the figure's).
enum class Aspect { Auto, Free, Equal };

/// One panel: its axes fit all series (with a margin); titles and axis labels with units. A
/// title equal to the figure's is not drawn again; long titles wrap.
struct Panel {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<Series> series;
  Aspect aspect = Aspect::Auto;
};

/// Panels stacked vertically, sharing the figure's width.
struct Figure {
  std::string title;        ///< drawn centred above the panels (wrapped); empty: none
  std::vector<Panel> panels;
  int width = 900;          ///< px
  int panel_height = 260;   ///< px of a panel without its title lines and legend rows
};

/// The SVG text of `figure`. @throws std::invalid_argument naming the panel and series when a
/// series has x and y of different sizes or no points, a value is not finite, or it has more marker
/// labels than markers.
std::string toSvg(const Figure& figure);

/// `text` with <, >, & and " written as entities: safe in SVG or HTML text and attribute values.
std::string escapeXml(const std::string& text);

/// Writes toSvg(figure) to `path`. @throws std::runtime_error naming the file when it cannot.
void writeSvg(const Figure& figure, const std::filesystem::path& path);

/// Estimated width [px] of `text` in the sans-serif font the SVG names (DejaVu Sans metrics, per
/// character class, rounded up) at `font_px`; bold adds 10 %. What the layout measures to wrap
/// titles and shorten legends so that they stay inside the figure.
double textWidth(std::string_view text, double font_px, bool bold = false);

/// `text` when it fits in `max_px`, else its head and tail around a "…" (a port name keeps its
/// component and its field: "NeedleAdmittance.adm…Pose.z").
std::string fitText(const std::string& text, double font_px, double max_px, bool bold = false);

/// `text` broken at spaces into lines of at most `max_px` (a word wider than that is fitText'd).
std::vector<std::string> wrapText(const std::string& text, double font_px, double max_px, bool bold = false);

/// The axis ranges of an equal-aspect panel: [x_low, x_high] and [y_low, y_high] widened about
/// their centres so that both spans take the same metres per pixel on a `width` x `height` px box.
void equalise(double& x_low, double& x_high, double& y_low, double& y_high, double width, double height);

/// Whether Aspect::Auto makes `panel` equal-aspect (both labels end in the same length unit).
bool equalAxes(const Panel& panel);

/// "Nice" tick values covering [low, high]: about `target` of them, at 1, 2 or 5 × 10^k steps.
std::vector<double> niceTicks(double low, double high, int target = 6);

}  // namespace cobra::plot
