#include "cobra/plot/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace cobra::plot {

std::string escapeXml(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

namespace {

// A colour-blind-safe palette (Okabe–Ito), cycled over the series of a panel; with a dash pattern
// and a marker shape per series, two series that coincide still show both.
constexpr const char* kColours[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000"};
constexpr const char* kDashes[] = {"", "8,3", "2,3", "10,3,2,3", "4,4"};
constexpr int kShapes = 5;          // circle, square, triangle, diamond, cross
constexpr int kMarkersPerLine = 7;  // markers spread along each non-dashed series
constexpr int kLeft = 80, kRight = 24, kPlotTop = 10, kAxisBelow = 46;  // px around a panel's plot box
constexpr double kTitlePx = 15, kFigureTitlePx = 17, kLegendPx = 12, kLineGap = 1.3;
constexpr double kLegendSample = 34, kLegendGap = 20, kLegendRow = 18;  // px

std::string escape(const std::string& text) { return escapeXml(text); }

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", std::abs(v) < 1e-12 ? 0.0 : v);
  return buffer;
}

struct Range {
  double low = std::numeric_limits<double>::infinity();
  double high = -std::numeric_limits<double>::infinity();
  void add(double v) {
    low = std::min(low, v);
    high = std::max(high, v);
  }
  /// Widens a flat range and adds 5 % so lines do not touch the frame.
  void settle(bool pad) {
    if (!(low <= high)) low = 0, high = 1;
    if (high - low < 1e-12) low -= 0.5, high += 0.5;
    if (pad) {
      const double margin = 0.05 * (high - low);
      low -= margin;
      high += margin;
    }
  }
};

void check(const Panel& panel, const Series& s) {
  const std::string where = "plot: panel '" + panel.title + "', series '" + s.label + "'";
  if (s.x.size() != s.y.size())
    throw std::invalid_argument(where + " has " + std::to_string(s.x.size()) + " x and " + std::to_string(s.y.size()) +
                                " y values; give as many of each");
  if (s.x.empty()) throw std::invalid_argument(where + " has no points");
  for (std::size_t i = 0; i < s.x.size(); ++i)
    if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]))
      throw std::invalid_argument(where + ": point " + std::to_string(i) + " is not finite");
  if (s.marker_x.size() != s.marker_y.size() || s.marker_labels.size() > s.marker_x.size())
    throw std::invalid_argument(where + " has " + std::to_string(s.marker_x.size()) + " marker x, " +
                                std::to_string(s.marker_y.size()) + " marker y and " +
                                std::to_string(s.marker_labels.size()) +
                                " marker labels; give as many x as y and at most one label per marker");
  for (std::size_t i = 0; i < s.marker_x.size(); ++i)
    if (!std::isfinite(s.marker_x[i]) || !std::isfinite(s.marker_y[i]))
      throw std::invalid_argument(where + ": marker " + std::to_string(i) + " is not finite");
}

// The SVG path of marker `shape` centred at (x, y), about 8 px across.
std::string markerPath(int shape, double x, double y) {
  char d[160];
  switch (shape % kShapes) {
    case 0: std::snprintf(d, sizeof d, "M%.1f,%.1fa3.6,3.6 0 1,0 7.2,0a3.6,3.6 0 1,0 -7.2,0", x - 3.6, y); break;
    case 1: std::snprintf(d, sizeof d, "M%.1f,%.1fh6.4v6.4h-6.4z", x - 3.2, y - 3.2); break;
    case 2: std::snprintf(d, sizeof d, "M%.1f,%.1fl4,7h-8z", x, y - 4.2); break;
    case 3: std::snprintf(d, sizeof d, "M%.1f,%.1fl4,4l-4,4l-4,-4z", x, y - 4); break;
    default: std::snprintf(d, sizeof d, "M%.1f,%.1fl7,7m0,-7l-7,7", x - 3.5, y - 3.5); break;
  }
  return d;
}

void drawMarker(std::ostringstream& svg, int shape, double x, double y, const char* colour) {
  const bool cross = shape % kShapes == kShapes - 1;
  svg << "<path class='marker' d='" << markerPath(shape, x, y) << "' fill='" << (cross ? "none" : colour)
      << "' stroke='" << (cross ? colour : "white") << "' stroke-width='" << (cross ? 2 : 0.8) << "'/>\n";
}

// A reference series is dashed '6,4'; the others take the patterns in turn, the first solid
// (counting only them: a measured path beside a dashed nominal one stays solid).
std::string dashOf(const Panel& panel, std::size_t k) {
  if (panel.series[k].dashed) return "6,4";
  const auto drawn = std::count_if(panel.series.begin(), panel.series.begin() + static_cast<std::ptrdiff_t>(k),
                                   [](const Series& s) { return !s.dashed; });
  return kDashes[static_cast<std::size_t>(drawn) % std::size(kDashes)];
}

// Writes `lines` (already wrapped) from baseline y, `gap` px apart.
void drawLines(std::ostringstream& svg, const std::vector<std::string>& lines, double x, double y, double font_px,
               const char* anchor) {
  for (std::size_t i = 0; i < lines.size(); ++i)
    svg << "<text x='" << number(x) << "' y='" << number(y + static_cast<double>(i) * font_px * kLineGap)
        << "' font-size='" << font_px << "' font-weight='bold' text-anchor='" << anchor << "'>" << escape(lines[i])
        << "</text>\n";
}

// The legend's entries, row by row: each (label as shown, x of its sample line).
struct LegendLayout {
  std::vector<std::string> labels;
  std::vector<double> x;
  std::vector<int> row;
  int rows = 0;
};

LegendLayout layoutLegend(const Panel& panel, int width) {
  LegendLayout legend;
  const double left = kLeft, right = width - kRight;
  double x = left;
  for (const Series& s : panel.series) {
    const std::string label = fitText(s.label, kLegendPx, right - left - kLegendSample - 6);
    const double w = kLegendSample + 6 + textWidth(label, kLegendPx);
    if (x > left && x + w > right) x = left, ++legend.rows;
    legend.labels.push_back(label);
    legend.x.push_back(x);
    legend.row.push_back(legend.rows);
    x += w + kLegendGap;
  }
  if (!panel.series.empty()) ++legend.rows;
  return legend;
}

// Draws `panel` from y = top; returns the height it took [px].
double drawPanel(std::ostringstream& svg, const Panel& panel, const std::string& figure_title, double top, int width,
                 int height) {
  Range xr, yr;
  for (const Series& s : panel.series) {
    check(panel, s);
    for (double v : s.x) xr.add(v);
    for (double v : s.y) yr.add(v);
    for (double v : s.marker_x) xr.add(v);
    for (double v : s.marker_y) yr.add(v);
  }
  const bool equal = panel.aspect == Aspect::Equal || (panel.aspect == Aspect::Auto && equalAxes(panel));
  xr.settle(equal);
  yr.settle(true);
  const double plot_w = width - kLeft - kRight;
  double plot_h = std::max(60, height - kPlotTop - kAxisBelow - 24);
  if (equal) {  // a tall path gets a taller box (up to 2.5 times the panel's), then the same m/px
    plot_h = std::clamp(plot_w * (yr.high - yr.low) / (xr.high - xr.low), plot_h, 2.5 * plot_h);
    equalise(xr.low, xr.high, yr.low, yr.high, plot_w, plot_h);
  }

  std::vector<std::string> title;
  if (panel.title != figure_title) title = wrapText(panel.title, kTitlePx, width - kLeft - kRight, true);
  const double title_h = title.empty() ? 0.0 : 8.0 + static_cast<double>(title.size()) * kTitlePx * kLineGap;
  drawLines(svg, title, kLeft, top + 8.0 + kTitlePx, kTitlePx, "start");
  const double box_top = top + title_h + kPlotTop;
  auto px = [&](double x) { return kLeft + (x - xr.low) / (xr.high - xr.low) * plot_w; };
  auto py = [&](double y) { return box_top + (yr.high - y) / (yr.high - yr.low) * plot_h; };

  svg << "<rect x='" << kLeft << "' y='" << number(box_top) << "' width='" << plot_w << "' height='" << plot_h
      << "' fill='none' stroke='#444'/>\n";
  for (double t : niceTicks(xr.low, xr.high)) {
    svg << "<line x1='" << number(px(t)) << "' y1='" << number(box_top) << "' x2='" << number(px(t)) << "' y2='"
        << number(box_top + plot_h) << "' stroke='#ddd'/>\n<text x='" << number(px(t)) << "' y='"
        << number(box_top + plot_h + 16) << "' font-size='11' text-anchor='middle'>" << number(t) << "</text>\n";
  }
  for (double t : niceTicks(yr.low, yr.high)) {
    svg << "<line x1='" << kLeft << "' y1='" << number(py(t)) << "' x2='" << kLeft + plot_w << "' y2='"
        << number(py(t)) << "' stroke='#ddd'/>\n<text x='" << kLeft - 6 << "' y='" << number(py(t) + 4)
        << "' font-size='11' text-anchor='end'>" << number(t) << "</text>\n";
  }
  svg << "<text x='" << number(kLeft + plot_w / 2) << "' y='" << number(box_top + plot_h + 36)
      << "' font-size='12' text-anchor='middle'>" << escape(fitText(panel.x_label, 12, plot_w)) << "</text>\n";
  svg << "<text transform='translate(18," << number(box_top + plot_h / 2) << ") rotate(-90)' font-size='12' "
      << "text-anchor='middle'>" << escape(fitText(panel.y_label, 12, plot_h)) << "</text>\n";

  const LegendLayout legend = layoutLegend(panel, width);
  const double legend_top = box_top + plot_h + kAxisBelow + 6;
  const std::size_t n = panel.series.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Series& s = panel.series[k];
    const char* colour = kColours[k % std::size(kColours)];
    const std::string dash = dashOf(panel, k);
    const int shape = static_cast<int>(k % kShapes);
    svg << "<polyline fill='none' stroke='" << colour << "' stroke-width='1.6'"
        << (dash.empty() ? "" : " stroke-dasharray='" + dash + "'") << " points='";
    for (std::size_t i = 0; i < s.x.size(); ++i) svg << number(px(s.x[i])) << ',' << number(py(s.y[i])) << ' ';
    svg << "'/>\n";
    // Style markers along the line, staggered per series: where lines coincide each shows its own.
    if (!s.dashed && s.x.size() > 1) {
      for (int m = 0; m < kMarkersPerLine; ++m) {
        const double target = (m + (static_cast<double>(k) + 0.5) / static_cast<double>(n)) / kMarkersPerLine;
        const auto i = std::min(s.x.size() - 1, static_cast<std::size_t>(target * static_cast<double>(s.x.size())));
        drawMarker(svg, shape, px(s.x[i]), py(s.y[i]), colour);
      }
    }
    for (std::size_t i = 0; i < s.marker_x.size(); ++i) {
      svg << "<circle cx='" << number(px(s.marker_x[i])) << "' cy='" << number(py(s.marker_y[i]))
          << "' r='3.5' fill='" << colour << "'/>\n";
      if (i < s.marker_labels.size())
        svg << "<text x='" << number(px(s.marker_x[i]) + 5) << "' y='" << number(py(s.marker_y[i]) - 6)
            << "' font-size='13' font-weight='bold' fill='" << colour << "'>" << escape(s.marker_labels[i])
            << "</text>\n";
    }
    const double lx = legend.x[k], ly = legend_top + kLegendRow * legend.row[k] + 6;
    svg << "<line x1='" << number(lx) << "' y1='" << number(ly) << "' x2='" << number(lx + kLegendSample - 4)
        << "' y2='" << number(ly) << "' stroke='" << colour << "' stroke-width='2'"
        << (dash.empty() ? "" : " stroke-dasharray='" + dash + "'") << "/>\n";
    if (!s.dashed) drawMarker(svg, shape, lx + (kLegendSample - 4) / 2, ly, colour);
    svg << "<text class='legend' x='" << number(lx + kLegendSample + 2) << "' y='" << number(ly + 4)
        << "' font-size='" << kLegendPx << "'>" << escape(legend.labels[k]) << "</text>\n";
  }
  return title_h + kPlotTop + plot_h + kAxisBelow + 6 + kLegendRow * legend.rows + 8;
}

double charWidth(unsigned char c) {  // em, DejaVu Sans advance widths rounded up
  if (c >= 0x80) return 0.34;          // a byte of a multi-byte character (about two bytes each)
  if (c == ' ') return 0.32;
  if (std::string_view("il.,:;!|'`").find(static_cast<char>(c)) != std::string_view::npos) return 0.30;
  if (std::string_view("fjrt()[]{}I-/\\\"").find(static_cast<char>(c)) != std::string_view::npos) return 0.42;
  if (c == 'm' || c == 'M' || c == 'W' || c == '@' || c == '%') return 1.0;
  if (c == 'w') return 0.83;
  if (c >= 'A' && c <= 'Z') return 0.74;
  if (c >= '0' && c <= '9') return 0.64;
  return 0.63;
}

}  // namespace

double textWidth(std::string_view text, double font_px, bool bold) {
  double em = 0.0;
  for (char c : text) em += charWidth(static_cast<unsigned char>(c));
  return em * font_px * (bold ? 1.1 : 1.0);
}

std::string fitText(const std::string& text, double font_px, double max_px, bool bold) {
  if (textWidth(text, font_px, bold) <= max_px) return text;
  static const std::string kEllipsis = "\xE2\x80\xA6";  // …
  // Keep the head and the tail (a port name's component and field), as much of each as fits.
  std::size_t head = text.size() / 2, tail = text.size() - head;
  auto shown = [&] { return text.substr(0, head) + kEllipsis + text.substr(text.size() - tail); };
  while (head + tail > 0 && textWidth(shown(), font_px, bold) > max_px) {
    if (head >= tail && head > 0) --head;
    else --tail;
  }
  // Do not cut inside a UTF-8 character.
  while (head > 0 && (static_cast<unsigned char>(text[head]) & 0xC0) == 0x80) --head;
  while (tail > 0 && (static_cast<unsigned char>(text[text.size() - tail]) & 0xC0) == 0x80) --tail;
  return shown();
}

std::vector<std::string> wrapText(const std::string& text, double font_px, double max_px, bool bold) {
  std::vector<std::string> lines;
  std::string line;
  std::istringstream words(text);
  for (std::string word; words >> word;) {
    const std::string longer = line.empty() ? word : line + ' ' + word;
    if (textWidth(longer, font_px, bold) <= max_px) {
      line = longer;
      continue;
    }
    if (!line.empty()) lines.push_back(line);
    line = fitText(word, font_px, max_px, bold);
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

void equalise(double& x_low, double& x_high, double& y_low, double& y_high, double width, double height) {
  const double per_px = std::max((x_high - x_low) / width, (y_high - y_low) / height);
  const double xc = (x_low + x_high) / 2, yc = (y_low + y_high) / 2;
  x_low = xc - per_px * width / 2, x_high = xc + per_px * width / 2;
  y_low = yc - per_px * height / 2, y_high = yc + per_px * height / 2;
}

bool equalAxes(const Panel& panel) {
  auto unit = [](const std::string& label) {
    const auto open = label.rfind('[');
    return open == std::string::npos || label.back() != ']' ? std::string() : label.substr(open);
  };
  const std::string x = unit(panel.x_label);
  return (x == "[m]" || x == "[mm]" || x == "[cm]") && x == unit(panel.y_label);
}

std::vector<double> niceTicks(double low, double high, int target) {
  std::vector<double> ticks;
  if (!(high > low) || target < 1) return ticks;
  const double raw = (high - low) / target;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double f : {1.0, 2.0, 5.0, 10.0})
    if (raw <= f * magnitude) {
      step = f * magnitude;
      break;
    }
  for (double t = std::ceil(low / step) * step; t <= high + step * 1e-9; t += step) ticks.push_back(t);
  return ticks;
}

std::string toSvg(const Figure& figure) {
  const std::vector<std::string> title = wrapText(figure.title, kFigureTitlePx, figure.width - 20, true);
  const double title_h = title.empty() ? 0.0 : 10.0 + static_cast<double>(title.size()) * kFigureTitlePx * kLineGap;
  std::ostringstream body;
  double y = title_h;
  drawLines(body, title, figure.width / 2.0, 6.0 + kFigureTitlePx, kFigureTitlePx, "middle");
  for (const Panel& panel : figure.panels) y += drawPanel(body, panel, figure.title, y, figure.width, figure.panel_height);
  std::ostringstream svg;
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << figure.width << "' height='" << std::ceil(y)
      << "' viewBox='0 0 " << figure.width << ' ' << std::ceil(y)
      << "' font-family='DejaVu Sans, sans-serif' style='max-width:100%;height:auto'>\n"
         "<rect width='100%' height='100%' fill='white'/>\n"
      << body.str() << "</svg>\n";
  return svg.str();
}

void writeSvg(const Figure& figure, const std::filesystem::path& path) {
  const std::string text = toSvg(figure);
  std::ofstream file(path);
  if (!(file << text)) throw std::runtime_error("plot: cannot write " + path.string());
}

}  // namespace cobra::plot
