#pragma once
/// @file
/// The report of a run as data: the event log, the chart-state timeline, figures, summary rows and
/// the files of the run folder. The runner and its observers fill it (Observer::report); whoever
/// renders it registers a ReportWriter (tools/report writes report.html; the `cobra` tool links
/// it). The runner itself writes the data files: events.csv (eventLogCsv) and signals.csv.

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "cobra/plot/svg_plot.hpp"

namespace cobra::run {

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

/// A figure of the report: panels of series, as cobra::plot draws them (plot/svg_plot.hpp: the
/// dependency-free plotting library below run; the report's HTML writer draws them with it).
using Series = plot::Series;
using Panel = plot::Panel;
using Figure = plot::Figure;

/// Everything the run's report shows.
struct RunReport {
  std::string title;
  std::vector<std::pair<std::string, std::string>> summary;  ///< key, value (with its unit)
  std::vector<EventRecord> events;
  std::vector<StateInterval> timeline;
  std::vector<Figure> figures;
  std::vector<std::string> files;  ///< other files of the run folder to link (e.g. "signals.csv")
};

/// The event log as CSV: `time [s],source,event,state`, one row per event, fields quoted when
/// they hold a comma or a quote.
std::string eventLogCsv(const std::vector<EventRecord>& events);

/// Renders `report` into the run folder `folder` (which exists, with events.csv and signals.csv
/// written) and returns the page it wrote (e.g. report.html). @throws std::runtime_error naming a
/// file it cannot write.
using ReportWriter = std::function<std::filesystem::path(const std::filesystem::path& folder, const RunReport& report)>;

}  // namespace cobra::run

/// The names tools/report (which renders these) and the applications' tests know them by.
namespace cobra::report {
using run::EventRecord;
using run::RunReport;
using run::StateInterval;
using run::TimelineRecorder;
}  // namespace cobra::report
