#pragma once
/// @file
/// Observers of a run as plug-ins (run/README.md, "Observers"). The runner loads a deployment,
/// steps it and ends the run; every other section of the application's `run` table names an
/// observer registered here: cobra's own (record, plots, summary, tracking, clearance, studio)
/// and any a package adds from its cobra_register_package (ObserverRegistry::add(package, ...)).
/// An observer owns its section's schema (its factory reads the section, errors naming the
/// file:line), its attach to the loaded deployment, its work at every observation and its part of
/// the result and the report. A section naming no registered observer is refused before the run,
/// naming the file:line and the known names.
///
/// Order: observers are made, attached, stepped and asked for their report part in the order
/// they were registered (cobra's own first), whatever the order of the sections in the file.
/// Threads: everything is called on the run's thread (the main thread; on the wall clock at
/// SCHED_FIFO priority 1 while the executor runs the deployment on its own).

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cobra/run/recording.hpp"
#include "cobra/run/report.hpp"
#include "cobra/run/run_spec.hpp"
#include "cobra/run/section.hpp"

namespace cobra::core {
class ComponentRegistry;
}
namespace cobra::deploy {
class Configurator;
class PackageBuilder;
}

namespace cobra::run {

struct RunResult;

/// A chart of `run.charts` as the runner observes it: one per entry, in their order, at addresses
/// that hold for the run.
struct ChartState {
  const ChartSpec* spec = nullptr;
  std::string state;     ///< full path of its active state now ("" before the first observation)
  std::string previous;  ///< full path one observation before
  bool changed = true;   ///< state != previous (or the first observation)
};

/// What an observer is given at attach: the loaded deployment and the run's shared parts, valid
/// until the run ended (Observer::finish).
struct ObserverContext {
  const RunSpec& spec;                      ///< the whole `run` table (step, charts, ...)
  const core::ComponentRegistry& components;  ///< the deployment: connect to ports by name (port_tap.hpp)
  const deploy::Configurator& configurator;  ///< deployments in force per scope, switchCount()
  const std::vector<const ChartState*>& charts;  ///< one per run.charts entry, updated before every step
  Recording& recording;                      ///< signals.csv: add columns here
  RunResult& result;                         ///< the result being built: fill your part
  bool realtime = false;                     ///< the wall clock (samples may be one period old)
  std::function<void(const std::string&)> say;  ///< prints a progress line, stamped with the run's time

  /// The chart of `run.charts` called `name`, or nullptr.
  const ChartState* chart(const std::string& name) const;
};

/// The run at one observation (Observer::step).
struct Moment {
  double t = 0.0;   ///< s of run time
  double dt = 0.0;  ///< s since the previous observation (the step on the lockstep clock; on the wall clock what passed)
  /// false: a further state a chart entered within the same observation (the wall clock: the
  /// charts' states between two observations, taken in turn): only work that follows chart
  /// states belongs there (ChartState::changed tells which), no port sampling.
  bool full = true;
  /// A row of the recording is taken right after this step: set your derived columns now.
  bool records = false;
};

/// One observer of a run, made from its section of the `run` table by its registered factory.
class Observer {
 public:
  virtual ~Observer() = default;
  /// Connects to the deployment by the names its section gave, adds its recorded columns and its
  /// entries of the result. @throws std::runtime_error "file:line: run.NAME: ..." for a name the
  /// deployment does not have (with what exists: deploy/suggest.hpp).
  virtual void attach(ObserverContext& run) = 0;
  /// After every observer attached (the columns they added exist). Default: nothing.
  virtual void attached(ObserverContext& /*run*/) {}
  /// Every observation (every `run.step` s), after the charts, events and switches were read.
  /// On the run's stepping path: allocate nothing once the run goes (size everything at attach),
  /// block on nothing. @throws std::runtime_error to stop the run with a message (a bad setup
  /// only seen with data, e.g. a joint count).
  virtual void step(const Moment& /*now*/) {}
  /// The run ended (its duration, events and outcome are in `result`): complete your part.
  virtual void finish(RunResult& /*result*/) {}
  /// Your part of the report: summary rows (after every observer's SummaryValue of
  /// RunResult::summary, which the runner shows), figures, files you wrote into the run folder.
  virtual void report(RunReport& /*report*/, const Recording& /*recording*/) const {}
};

/// Reads an observer's section and makes the observer. @throws std::runtime_error via
/// Section::fail for a bad section.
using ObserverFactory = std::function<std::unique_ptr<Observer>(const Section& section)>;

/// The observers known by name, for the process (as core::BackendRegistry for devices). Used from
/// the deployer's thread (packages register while the files load, the runner reads the run table
/// after).
class ObserverRegistry {
 public:
  struct Kind {
    std::string name, doc;
    std::string owner;  ///< "cobra", or "package 'NAME'"
    ObserverFactory make;
  };
  /// Registers the observer of the `run` table's section `name`.
  /// @throws std::runtime_error when another owner registered `name` (the same owner replaces
  ///         its own: a package loaded again).
  static void add(std::string name, std::string doc, ObserverFactory make, std::string owner = "cobra");
  /// The same from a package's cobra_register_package: owned by the package.
  static void add(deploy::PackageBuilder& package, std::string name, std::string doc, ObserverFactory make);
  /// The observer called `name`, or nullptr.
  static const Kind* find(const std::string& name);
  /// Every registered name, in registration order.
  static std::vector<std::string> names();
  /// Every registered kind, in registration order.
  static std::vector<Kind> kinds();

  /// Registers a renderer of the run folder's report (tools/report's "html"); a second writer of
  /// the same name replaces the first. The runner calls every writer after writing events.csv and
  /// signals.csv; RunResult::report is the page the first one wrote.
  static void addReportWriter(const std::string& name, ReportWriter writer);
  static std::vector<ReportWriter> reportWriters();
};

}  // namespace cobra::run
