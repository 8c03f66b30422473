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

// A colour-blind-safe palette (Okabe–Ito), cycled over the series of a panel.
constexpr const char* kColours[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000"};
constexpr int kLeft = 80, kRight = 170, kTop = 34, kBottom = 46;  // px of a panel's margins (legend at the right)

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

void drawPanel(std::ostringstream& svg, const Panel& panel, int top, int width, int height) {
  Range xr, yr;
  for (const Series& s : panel.series) {
    check(panel, s);
    for (double v : s.x) xr.add(v);
    for (double v : s.y) yr.add(v);
    for (double v : s.marker_x) xr.add(v);
    for (double v : s.marker_y) yr.add(v);
  }
  xr.settle(false);
  yr.settle(true);
  const double plot_w = width - kLeft - kRight, plot_h = height - kTop - kBottom;
  auto px = [&](double x) { return kLeft + (x - xr.low) / (xr.high - xr.low) * plot_w; };
  auto py = [&](double y) { return top + kTop + (yr.high - y) / (yr.high - yr.low) * plot_h; };

  svg << "<text x='" << kLeft << "' y='" << top + 22 << "' font-size='15' font-weight='bold'>" << escape(panel.title)
      << "</text>\n";
  svg << "<rect x='" << kLeft << "' y='" << top + kTop << "' width='" << plot_w << "' height='" << plot_h
      << "' fill='none' stroke='#444'/>\n";
  for (double t : niceTicks(xr.low, xr.high)) {
    svg << "<line x1='" << px(t) << "' y1='" << top + kTop << "' x2='" << px(t) << "' y2='" << top + kTop + plot_h
        << "' stroke='#ddd'/>\n<text x='" << px(t) << "' y='" << top + kTop + plot_h + 16
        << "' font-size='11' text-anchor='middle'>" << number(t) << "</text>\n";
  }
  for (double t : niceTicks(yr.low, yr.high)) {
    svg << "<line x1='" << kLeft << "' y1='" << py(t) << "' x2='" << kLeft + plot_w << "' y2='" << py(t)
        << "' stroke='#ddd'/>\n<text x='" << kLeft - 6 << "' y='" << py(t) + 4
        << "' font-size='11' text-anchor='end'>" << number(t) << "</text>\n";
  }
  svg << "<text x='" << kLeft + plot_w / 2 << "' y='" << top + height - 8 << "' font-size='12' text-anchor='middle'>"
      << escape(panel.x_label) << "</text>\n";
  svg << "<text transform='translate(18," << top + kTop + plot_h / 2 << ") rotate(-90)' font-size='12' "
      << "text-anchor='middle'>" << escape(panel.y_label) << "</text>\n";

  for (std::size_t k = 0; k < panel.series.size(); ++k) {
    const Series& s = panel.series[k];
    const char* colour = kColours[k % std::size(kColours)];
    svg << "<polyline fill='none' stroke='" << colour << "' stroke-width='1.6'"
        << (s.dashed ? " stroke-dasharray='6,4'" : "") << " points='";
    for (std::size_t i = 0; i < s.x.size(); ++i) svg << px(s.x[i]) << ',' << py(s.y[i]) << ' ';
    svg << "'/>\n";
    for (std::size_t i = 0; i < s.marker_x.size(); ++i) {
      svg << "<circle cx='" << px(s.marker_x[i]) << "' cy='" << py(s.marker_y[i]) << "' r='3.5' fill='" << colour
          << "'/>\n";
      if (i < s.marker_labels.size())
        svg << "<text x='" << px(s.marker_x[i]) + 5 << "' y='" << py(s.marker_y[i]) - 6
            << "' font-size='13' font-weight='bold' fill='" << colour << "'>" << escape(s.marker_labels[i])
            << "</text>\n";
    }
    const double ly = top + kTop + 14 + 18.0 * static_cast<double>(k);
    svg << "<line x1='" << width - kRight + 12 << "' y1='" << ly << "' x2='" << width - kRight + 36 << "' y2='" << ly
        << "' stroke='" << colour << "' stroke-width='2'" << (s.dashed ? " stroke-dasharray='6,4'" : "") << "/>\n"
        << "<text x='" << width - kRight + 42 << "' y='" << ly + 4 << "' font-size='12'>" << escape(s.label)
        << "</text>\n";
  }
}

}  // namespace

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
  const int title_height = figure.title.empty() ? 0 : 30;
  const int height = title_height + figure.panel_height * static_cast<int>(figure.panels.size());
  std::ostringstream svg;
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << figure.width << "' height='" << height
      << "' font-family='sans-serif'>\n<rect width='100%' height='100%' fill='white'/>\n";
  if (!figure.title.empty())
    svg << "<text x='" << figure.width / 2 << "' y='22' font-size='17' text-anchor='middle' font-weight='bold'>"
        << escape(figure.title) << "</text>\n";
  for (std::size_t i = 0; i < figure.panels.size(); ++i)
    drawPanel(svg, figure.panels[i], title_height + figure.panel_height * static_cast<int>(i), figure.width,
              figure.panel_height);
  svg << "</svg>\n";
  return svg.str();
}

void writeSvg(const Figure& figure, const std::filesystem::path& path) {
  const std::string text = toSvg(figure);
  std::ofstream file(path);
  if (!(file << text)) throw std::runtime_error("plot: cannot write " + path.string());
}

}  // namespace cobra::plot
