#pragma once
/// @file
/// The report of one run of an application (the puncturing demo, the door example): a folder with
/// a machine-readable event log, the recorded ports (written by the Reporter component) and an
/// HTML page with a timeline of every chart's states, plots and a summary. No dependency beyond
/// cobra::plot; the page is self-contained (inline SVG, no script, no download).

#include <filesystem>
#include <string>
#include <vector>

#include "cobra/plot/svg_plot.hpp"

namespace cobra::report {

/// One event seen during the run: when [s, simulated or wall time], who raised it, its name, and
/// the state of the chart that received it right after it was handled ("" when none did).
struct EventRecord {
  double time = 0.0;
  std::string source;
  std::string event;
  std::string state;
};

/// A chart stayed in `state` from `begin` to `end` [s].
struct StateInterval {
  std::string chart;
  std::string state;
  double begin = 0.0;
  double end = 0.0;
};

/// Turns state changes observed over time into intervals, one lane per chart.
class TimelineRecorder {
 public:
  /// Records that `chart` is in `state` at `time` [s]; only changes start a new interval.
  /// @throws std::invalid_argument when time goes backwards for that chart.
  void observe(double time, const std::string& chart, const std::string& state);
  /// The intervals so far, the open one of each chart closed at `end_time` [s].
  std::vector<StateInterval> intervals(double end_time) const;
  /// Every state each chart entered, in order of first entry.
  std::vector<std::string> statesEntered(const std::string& chart) const;

 private:
  std::vector<StateInterval> closed_;
  std::vector<StateInterval> open_;  // one per chart, end unused
};

/// Everything the HTML page shows.
struct RunReport {
  std::string title;
  std::vector<std::pair<std::string, std::string>> summary;  ///< key, value (with its unit)
  std::vector<EventRecord> events;
  std::vector<StateInterval> timeline;
  std::vector<plot::Figure> figures;
  std::vector<std::string> files;  ///< other files of the run folder to link (e.g. "signals.csv")
};

/// The event log as CSV: `time [s],source,event,state`, one row per event, fields quoted when
/// they hold a comma or a quote.
std::string eventLogCsv(const std::vector<EventRecord>& events);

/// A Gantt-like SVG: one lane per chart, one box per interval, labelled with the state's leaf
/// name when it fits (the full name is the box's tooltip).
std::string timelineSvg(const std::vector<StateInterval>& timeline, int width = 900);

/// The self-contained HTML page of `report`.
std::string toHtml(const RunReport& report);

/// Writes `events.csv` and `report.html` into `folder` (created if needed).
/// @return the path of report.html. @throws std::runtime_error naming the file it cannot write.
std::filesystem::path writeRunFolder(const std::filesystem::path& folder, const RunReport& report);

}  // namespace cobra::report
