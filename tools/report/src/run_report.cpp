#include "cobra/report/run_report.hpp"

#include "cobra/run/observer.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace cobra::report {
namespace {

// Okabe–Ito palette, as cobra::plot uses; a state keeps its colour across lanes.
constexpr const char* kColours[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#999999"};
constexpr int kLaneHeight = 34, kLabelWidth = 150, kAxisHeight = 30;  // px
constexpr double kCharWidth = 6.5;                                     // px of a 11 px sans-serif character

std::string escape(const std::string& text) { return plot::escapeXml(text); }

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
  std::map<std::string, std::size_t> colour_of;
  double t0 = 0.0, t1 = 1.0;
  bool first = true;
  for (const StateInterval& s : timeline) {
    if (std::find(charts.begin(), charts.end(), s.chart) == charts.end()) charts.push_back(s.chart);
    colour_of.emplace(leaf(s.state), colour_of.size());
    t0 = first ? s.begin : std::min(t0, s.begin);
    t1 = first ? s.end : std::max(t1, s.end);
    first = false;
  }
  if (t1 - t0 < 1e-9) t1 = t0 + 1.0;
  const int plot_width = width - kLabelWidth - 20;
  const int height = static_cast<int>(charts.size()) * kLaneHeight + kAxisHeight;
  auto x = [&](double t) { return kLabelWidth + (t - t0) / (t1 - t0) * plot_width; };
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
      << "\" font-family=\"sans-serif\" font-size=\"11\">\n";
  for (std::size_t lane = 0; lane < charts.size(); ++lane) {
    const int y = static_cast<int>(lane) * kLaneHeight;
    svg << "<text x=\"4\" y=\"" << y + kLaneHeight / 2 + 4 << "\" font-weight=\"bold\">" << escape(charts[lane])
        << "</text>\n";
    for (const StateInterval& s : timeline) {
      if (s.chart != charts[lane]) continue;
      const double left = x(s.begin), w = std::max(1.0, x(s.end) - left);
      const char* colour = kColours[colour_of[leaf(s.state)] % std::size(kColours)];
      svg << "<g><title>" << escape(s.state) << ": " << number(s.begin) << " s to " << number(s.end)
          << " s</title><rect x=\"" << number(left) << "\" y=\"" << y + 4 << "\" width=\"" << number(w)
          << "\" height=\"" << kLaneHeight - 8 << "\" fill=\"" << colour << "\" fill-opacity=\"0.75\" stroke=\"#fff\"/>";
      const std::string label = leaf(s.state);
      if (static_cast<double>(label.size()) * kCharWidth + 4 < w)
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
  svg << "</svg>\n";
  return svg.str();
}

std::string toHtml(const RunReport& report) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << escape(report.title) << "</title>\n"
       << "<style>body{font-family:sans-serif;margin:2em;max-width:960px}table{border-collapse:collapse}"
          "td,th{border:1px solid #ccc;padding:3px 8px;text-align:left}th{background:#eee}"
          ".events{max-height:420px;overflow-y:scroll}</style></head><body>\n"
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
  for (const run::Figure& figure : report.figures)
    html << "<h2>" << escape(figure.title) << "</h2>\n" << plot::toSvg(figure);
  html << "<h2>Events</h2>\n<div class=\"events\"><table>\n<tr><th>t [s]</th><th>source</th><th>event</th><th>state "
          "after</th></tr>\n";
  for (const EventRecord& e : report.events)
    html << "<tr><td>" << number(e.time, "%.3f") << "</td><td>" << escape(e.source) << "</td><td>" << escape(e.event)
         << "</td><td>" << escape(e.state) << "</td></tr>\n";
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
