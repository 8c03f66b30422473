#include "cobra/report/run_report.hpp"

#include "cobra/run/observer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace cobra::report {
namespace {

// Okabe–Ito, then Paul Tol's muted palette: a lane's states take them in order of first entry, so
// the states of one lane differ in colour (up to 15 of them) and the legend below names each.
constexpr const char* kColours[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00",
                                    "#56B4E9", "#999999", "#332288", "#88CCEE", "#44AA99",
                                    "#117733", "#999933", "#DDCC77", "#CC6677", "#882255"};
constexpr int kLaneHeight = 34, kLabelWidth = 150, kAxisHeight = 36, kLegendRow = 18;  // px
constexpr double kFontPx = 11;

std::string escape(const std::string& text) { return plot::escapeXml(text); }

/// `state` escaped, with a line break allowed after each dot: a long dotted state path wraps at
/// its parts instead of widening the events table beyond the page.
std::string breakable(const std::string& state) {
  std::string out;
  for (const char c : escape(state)) out += c == '.' ? std::string(".<wbr>") : std::string(1, c);
  return out;
}

std::string number(double v, const char* format = "%.6g") {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

/// "root.InsertingNeedles.MoveToSkin" -> "MoveToSkin".
std::string leaf(const std::string& state) {
  const auto dot = state.rfind('.');
  return dot == std::string::npos ? state : state.substr(dot + 1);
}

void writeFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("run report: cannot write " + path.string());
}

}  // namespace

std::string timelineSvg(const std::vector<StateInterval>& timeline, int width) {
  std::vector<std::string> charts;
  std::vector<std::vector<std::string>> states;  // per lane: leaf names in order of first entry
  double t0 = 0.0, t1 = 1.0;
  bool first = true;
  for (const StateInterval& s : timeline) {
    auto lane = std::find(charts.begin(), charts.end(), s.chart);
    if (lane == charts.end()) charts.push_back(s.chart), states.emplace_back(), lane = charts.end() - 1;
    std::vector<std::string>& known = states[static_cast<std::size_t>(lane - charts.begin())];
    if (std::find(known.begin(), known.end(), leaf(s.state)) == known.end()) known.push_back(leaf(s.state));
    t0 = first ? s.begin : std::min(t0, s.begin);
    t1 = first ? s.end : std::max(t1, s.end);
    first = false;
  }
  if (t1 - t0 < 1e-9) t1 = t0 + 1.0;
  const int plot_width = width - kLabelWidth - 20;
  auto colourOf = [&](std::size_t lane, const std::string& state) {
    const auto& known = states[lane];
    return kColours[static_cast<std::size_t>(std::find(known.begin(), known.end(), state) - known.begin()) %
                    std::size(kColours)];
  };
  // The legend: per lane, its name then a swatch and the name of each of its states, wrapped.
  std::ostringstream legend;
  double legend_y = static_cast<double>(charts.size()) * kLaneHeight + kAxisHeight + 14;
  for (std::size_t lane = 0; lane < charts.size(); ++lane) {
    legend << "<text x=\"4\" y=\"" << number(legend_y) << "\" font-weight=\"bold\">"
           << escape(plot::fitText(charts[lane], kFontPx, kLabelWidth - 8, true)) << "</text>\n";
    double x = kLabelWidth;
    for (const std::string& state : states[lane]) {
      const std::string label = plot::fitText(state, kFontPx, plot_width - 16);
      const double w = 14 + plot::textWidth(label, kFontPx) + 12;
      if (x > kLabelWidth && x + w > width - 10) x = kLabelWidth, legend_y += kLegendRow;
      legend << "<rect class=\"swatch\" x=\"" << number(x) << "\" y=\"" << number(legend_y - 9) << "\" width=\"10\" "
             << "height=\"10\" fill=\"" << colourOf(lane, state) << "\"/><text x=\"" << number(x + 14) << "\" y=\""
             << number(legend_y) << "\">" << escape(label) << "</text>\n";
      x += w;
    }
    legend_y += kLegendRow + 4;
  }
  const int height = static_cast<int>(std::ceil(legend_y));
  auto x = [&](double t) { return kLabelWidth + (t - t0) / (t1 - t0) * plot_width; };
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
      << "\" viewBox=\"0 0 " << width << ' ' << height
      << "\" font-family=\"DejaVu Sans, sans-serif\" font-size=\"11\" style=\"max-width:100%;height:auto\">\n";
  for (std::size_t lane = 0; lane < charts.size(); ++lane) {
    const int y = static_cast<int>(lane) * kLaneHeight;
    svg << "<text x=\"4\" y=\"" << y + kLaneHeight / 2 + 4 << "\" font-weight=\"bold\">"
        << escape(plot::fitText(charts[lane], kFontPx, kLabelWidth - 8, true)) << "</text>\n";
    for (const StateInterval& s : timeline) {
      if (s.chart != charts[lane]) continue;
      const double left = x(s.begin), w = std::max(1.0, x(s.end) - left);
      svg << "<g><title>" << escape(s.state) << ": " << number(s.begin) << " s to " << number(s.end)
          << " s</title><rect x=\"" << number(left) << "\" y=\"" << y + 4 << "\" width=\"" << number(w)
          << "\" height=\"" << kLaneHeight - 8 << "\" fill=\"" << colourOf(lane, leaf(s.state))
          << "\" fill-opacity=\"0.85\" stroke=\"#fff\"/>";
      const std::string label = leaf(s.state);
      if (plot::textWidth(label, kFontPx) + 6 < w)
        svg << "<text x=\"" << number(left + 3) << "\" y=\"" << y + kLaneHeight / 2 + 4 << "\" fill=\"#fff\">"
            << escape(label) << "</text>";
      svg << "</g>\n";
    }
  }
  const int axis_y = static_cast<int>(charts.size()) * kLaneHeight;
  svg << "<line x1=\"" << kLabelWidth << "\" y1=\"" << axis_y << "\" x2=\"" << kLabelWidth + plot_width << "\" y2=\""
      << axis_y << "\" stroke=\"#333\"/>\n";
  for (double t : plot::niceTicks(t0, t1, 8)) {
    if (t < t0 || t > t1) continue;
    svg << "<text x=\"" << number(x(t)) << "\" y=\"" << axis_y + 16 << "\" text-anchor=\"middle\">" << number(t)
        << "</text>\n";
  }
  svg << "<text x=\"" << kLabelWidth + plot_width << "\" y=\"" << axis_y + 28 << "\" text-anchor=\"end\">t [s]</text>\n";
  svg << legend.str() << "</svg>\n";
  return svg.str();
}

std::string toHtml(const RunReport& report) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << escape(report.title) << "</title>\n"
       << "<style>body{font-family:sans-serif;margin:2em;max-width:960px}table{border-collapse:collapse}"
          "td,th{border:1px solid #ccc;padding:3px 8px;text-align:left}th{background:#eee}"
          ".events{max-height:420px;overflow:auto}.events td:first-child{white-space:nowrap}</style></head><body>\n"
       << "<h1>" << escape(report.title) << "</h1>\n<h2>Summary</h2>\n<table>\n";
  for (const auto& [key, value] : report.summary)
    html << "<tr><th>" << escape(key) << "</th><td>" << escape(value) << "</td></tr>\n";
  html << "</table>\n";
  if (!report.files.empty()) {
    html << "<p>Files of this run: ";
    for (std::size_t i = 0; i < report.files.size(); ++i)
      html << (i ? ", " : "") << "<a href=\"" << escape(report.files[i]) << "\">" << escape(report.files[i]) << "</a>";
    html << "</p>\n";
  }
  html << "<h2>Task states</h2>\n" << timelineSvg(report.timeline);
  // The figure's title is the section's heading, drawn once: not again in the SVG, nor as the title
  // of a panel that repeats it.
  for (run::Figure figure : report.figures) {
    html << "<h2>" << escape(figure.title) << "</h2>\n";
    for (run::Panel& panel : figure.panels)
      if (panel.title == figure.title) panel.title.clear();
    figure.title.clear();
    html << plot::toSvg(figure);
  }
  html << "<h2>Events</h2>\n<div class=\"events\"><table>\n<tr><th>t [s]</th><th>source</th><th>event</th><th>state "
          "after</th></tr>\n";
  for (const EventRecord& e : report.events)
    html << "<tr><td>" << number(e.time, "%.3f") << "</td><td>" << escape(e.source) << "</td><td>" << escape(e.event)
         << "</td><td>" << breakable(e.state) << "</td></tr>\n";
  html << "</table></div>\n</body></html>\n";
  return html.str();
}

std::filesystem::path writeRunFolder(const std::filesystem::path& folder, const RunReport& report) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw std::runtime_error("run report: cannot create folder " + folder.string() + ": " + error.message());
  writeFile(folder / "events.csv", eventLogCsv(report.events));
  return writeHtml(folder, report);
}

std::filesystem::path writeHtml(const std::filesystem::path& folder, const RunReport& report) {
  const std::filesystem::path page = folder / "report.html";
  writeFile(page, toHtml(report));
  return page;
}

void registerHtmlReport() { run::ObserverRegistry::addReportWriter("html", &writeHtml); }

}  // namespace cobra::report
