#pragma once
// The runner's observers, attached to a deployment by the names the application's `run` table
// gives: recorded columns, tracked tools, the clearance, summary values. Private to cobra::run.

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/core/introspection.hpp"
#include "cobra/plot/svg_plot.hpp"
#include "cobra/run/run_spec.hpp"
#include "cobra/run/runner.hpp"
#include "cobra/run/tracking.hpp"
#include "cobra/run/port_tap.hpp"

namespace cobra::run {

struct Chart;

// Columns sampled every record period: the recorded ports' fields and the derived figures
// (tracking errors, clearance), by name ("Comp.port", "Comp.port.z", "tracking.NAME.mm").
class Recording {
 public:
  // Adds `path` (a port) unless recorded already. @throws as NumericTap.
  void addPort(const core::ComponentRegistry& registry, const std::string& path, const std::string& where,
               const std::string& use);
  // A derived column, filled by `sample`'s caller through `set`.
  std::size_t addDerived(const std::string& name, const std::string& unit);
  void set(std::size_t derived, double value) { derived_now_[derived] = value; }
  // One row at time `t` [s]: every port's newest value, the derived values set since.
  void sample(double t);

  // The names of every column a plot may name (for messages), after at least one sample.
  std::vector<std::string> columnNames() const;
  // The column `name`'s samples; false when it does not exist.
  bool column(const std::string& name, std::vector<double>& x, std::vector<double>& y) const;
  // Whether `name` names a recorded port or field, or a derived column, or a port that has
  // fields (then `fields` lists them).
  bool knows(const std::string& name, std::vector<std::string>& fields) const;
  std::string unitOf(const std::string& name) const;
  // signals.csv: "time [s],NAME [unit],...", one row per sample.
  std::string csv() const;

 private:
  struct Port {
    std::unique_ptr<NumericTap> tap;
    std::vector<std::vector<double>> rows;  // one per sample (empty: no data yet)
    std::size_t width = 0;
  };
  std::vector<Port> ports_;
  std::vector<std::pair<std::string, std::string>> derived_;  // name, unit
  std::vector<double> derived_now_;
  std::vector<std::vector<double>> derived_rows_;
  std::vector<double> times_;
  std::vector<double> scratch_;
};

// One `run.tracking` entry: its taps and monitor.
struct Tracker {
  TrackingSpec spec;
  std::unique_ptr<Tap<KDL::Frame>> commanded, measured;
  std::unique_ptr<Tap<KDL::JntArray>> joints;
  std::unique_ptr<TrackingMonitor> monitor;
  std::size_t limits = 0;  // joint velocity limits given
  std::size_t mm_column = 0, deg_column = 0;
  const Chart* chart = nullptr;  // spec.chart's (nullptr: none)
  KDL::JntArray joint_sample;    // the joints' last sample (kept: reading it allocates once)
  bool counts = false;           // spec.scope's deployment is one of spec.counts_while (or none given)
};

// `run.clearance`: the port's samples against the threshold, the contacts apart.
struct ClearanceObserver {
  ClearanceSpec spec;
  std::unique_ptr<Tap<double>> clearance;
  std::vector<std::unique_ptr<Tap<double>>> contacts;
  std::vector<bool> paused;  // per pause
  std::vector<const Chart*> pause_charts;  // per pause: its chart
  std::size_t column = 0, threshold_column = 0;
  std::vector<std::size_t> contact_columns;
  double last = std::numeric_limits<double>::quiet_NaN();
};

// `run.summary` entries that sample ports.
struct SummaryObserver {
  SummarySpec spec;
  std::vector<std::unique_ptr<Tap<KDL::Frame>>> frames;  // Distance
  std::unique_ptr<Tap<double>> value;                    // Port
};

// The figures of the report: the declared plots, one per tracked tool, the clearance. `timeline`
// (lanes "<chart> chart") places the marks of the plots' paths.
std::vector<plot::Figure> reportFigures(const RunSpec& spec, const Recording& recording,
                                        const std::vector<Tracker>& trackers, const ClearanceObserver* clearance,
                                        const std::vector<report::StateInterval>& timeline);

// The summary rows of the fidelity figures.
std::vector<std::pair<std::string, std::string>> fidelityRows(const RunResult& result, const RunSpec& spec);
// The executor's timing (wall clock): ticks, misses, latency, compute, the `components` slowest.
std::vector<std::pair<std::string, std::string>> executorRows(const ExecutorFigures& executor, std::size_t components);
// "median 3.1 us, p99 ..., worst ... (n samples)".
std::string executorTimingText(const core::DurationFigures& figures);

// "%8.3f s".
std::string seconds(double t);
bool startsWith(const std::string& text, const std::string& prefix);

}  // namespace cobra::run
