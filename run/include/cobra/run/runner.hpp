#pragma once
/// @file
/// The generic application runner behind `cobra run APP`: loads an application's entry file (its
/// deployment, with the `run = { ... }` table that says what ends the run and what to observe,
/// run/README.md), plays its declared actions and a faults file, steps the clock until the task
/// charts reach their final states, and writes the run folder (events.csv, signals.csv,
/// report.html). It knows no application: every name it uses comes from the application's files.

#include <atomic>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "cobra/core/lockstep_clock.hpp"
#include "cobra/core/realtime_executor.hpp"
#include "cobra/run/report.hpp"
#include "cobra/run/tracking.hpp"
#include "cobra/statechart/description.hpp"

namespace cobra::deploy {
class Configurator;
class PackageRegistry;
}
namespace cobra::core {
class ComponentRegistry;
}

namespace cobra::run {

struct RunSpec;
struct RunResult;

/// What a run observer is shown of a run at setup (RunObserver::attach).
struct RunContext {
  const RunSpec& spec;                      ///< the `run` table (run.studio: what to show)
  const core::ComponentRegistry& registry;  ///< the deployment, to connect to ports by name
  std::filesystem::path entry;              ///< the application's entry file
  std::filesystem::path scenario;           ///< "" = the application's default
  std::filesystem::path report_folder;      ///< "" = no report
  double clearance_threshold = 0.0;         ///< m (run.clearance; 0 when not declared)
  /// Each chart of `run.charts` (in its order) as its supervisor loaded it: states, transitions.
  std::vector<statechart::ChartDescription> charts;
  /// The deployment scopes of `run.charts` ("" is the default scope), in order of first mention.
  std::vector<std::string> scopes;
  /// The run's Configurator, to describe the deployment at setup (cobra edit's running view);
  /// use it on the run's thread only (attach, step, finished).
  const deploy::Configurator* configurator = nullptr;
};

/// The run between two instants of its clock, for RunObserver::step. States are per chart of
/// `run.charts`, deployments and configurations per scope of RunContext::scopes, in their order.
struct StepView {
  double t = 0.0;                                  ///< s of run time
  const std::vector<const std::string*>& states;   ///< each chart's active state (full path)
  const std::vector<std::string>& deployments;     ///< each scope's deployment in force ("": none yet)
  /// Each scope's configuration in force: the last one applied that sets a property of a
  /// component of the scope's deployment (one that sets none of any scope's applies to all).
  const std::vector<std::string>& configurations;
  const std::string& configuration;  ///< the configuration applied last, whatever its scope
  double clearance = 0.0;  ///< m, the last clearance sample (NaN: none or paused)
};

/// Something that watches a run from the run's own thread (cobra studio's Robot Visualizer Bridge,
/// studio/README.md): connected at setup, called once per step after the runner's observation,
/// told of every event and chart state entry, and asked for inputs to play (e.g. a surgeon's
/// button: run.studio.inputs). step() must not block the run: it is on the runner's step.
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  /// @throws std::runtime_error naming the entry file:line and what is wrong (an unknown port).
  virtual void attach(const RunContext& run) = 0;
  virtual void step(const StepView& now) = 0;
  /// An event of a component's `events` or a supervisor's `outputEvents` (`source` the component),
  /// or a chart entering a state (`source` the chart's name, `name` the state's folded path).
  virtual void event(double t, const std::string& source, const std::string& name) = 0;
  /// The next input to play (an index into run.studio.inputs); false when none is waiting.
  virtual bool nextInput(std::size_t& index) = 0;
  /// The run ended (before the run folder is written). Returns files it wrote into the report
  /// folder for the report to link (relative paths).
  virtual std::vector<std::string> finished(const RunResult& result) = 0;
};

struct RunOptions {
  /// The application: an entry file, or a folder holding `<folder name>.lua`.
  std::filesystem::path app;
  /// Scenario folder, given to the entry file as the global `scenario` before it runs; empty:
  /// the application's default. A `faults.lua` in it is played unless `faults_file` is given.
  std::filesystem::path scenario;
  /// Time after which the run stops unfinished [s] (simulated on the lockstep clock).
  double time_limit = 900.0;
  /// Where to write the run folder; empty: no report.
  std::filesystem::path report_folder;
  /// A faults file (run/README.md: faults.lua); empty: the scenario's faults.lua when present.
  std::filesystem::path faults_file;
  /// The wall clock instead of the lockstep simulation clock: the deployment's schedule run by a
  /// real-time executor (core/realtime_executor.hpp; setExecutor in the files sets it up).
  bool realtime = false;
  /// With `realtime`: every component on a thread of its own (ClockMode::RealTime) instead of the
  /// executor, for a deployment that asks for it.
  bool thread_per_component = false;
  /// Called with one line per task state change, per switch, per fault and every
  /// `progress_every` s of run time (nullptr: quiet).
  std::function<void(const std::string&)> progress;
  double progress_every = 10.0;  ///< s
  /// Lua run before the entry file (after `scenario` is set), e.g. a test's surgeon script.
  std::string before_lua;
  /// Lua run after the entry file (a property to change for a test).
  std::string extra_lua;
  /// Called after every component step with its wall-clock duration (lockstep clock only).
  core::LockstepClock::StepObserver step_observer;
  /// Registers packages beside cobra's built-in ones (components::addBuiltinPackages).
  std::function<void(deploy::PackageRegistry&)> add_packages;
  /// Lockstep clock only: simulated s per wall s the run is held to (1 = real time; 0 = as fast
  /// as the CPU goes, the default).
  double pace = 0.0;
  /// Given to the entry file as the global `interactive = true` before it runs: the application
  /// lets a person give the surgeon's inputs (e.g. no surgeon script; run.studio.inputs).
  bool interactive = false;
  /// Watches the run from its thread (cobra studio's bridge); nullptr: none.
  RunObserver* observer = nullptr;
  /// When set and true, the run ends after the current step (Ctrl-C): Outcome::Interrupted.
  const std::atomic<bool>* interrupt = nullptr;
  /// s the run steps on after its outcome is decided (completed, safe stop, component error,
  /// time limit; not after an interrupt), the outcome and reason unchanged: the robots are watched
  /// (observers, recording, RunObserver) holding after it (cobra faults matrix). 0: it ends at once.
  double watch_after_end = 0.0;
  /// This process's host in the application's `placement` (deploy/placement.hpp): only that
  /// host's components run here, the connections to the others' go over the placement's
  /// transport, and the run table's entries naming other hosts' components are left to them.
  /// "" (default): the placement is ignored, everything runs in this process.
  std::string host;
};

/// The event the runner writes into the inputEvents of every chart of `run.charts` (when one has a
/// safe stop) as soon as a component enters Exception or FatalError, its source that component:
/// a chart lists it among its failures (as `e_component_error`, or `e_component_error@Comp`) and
/// goes to its safe stop; the run's reason then names the component and its lastError.
inline constexpr const char* kComponentErrorEvent = "e_component_error";

enum class Outcome {
  Completed,       ///< every task chart reached its done state
  TimeLimit,       ///< the time limit came first
  /// A component went to Exception or FatalError, and no chart with a safe stop reached it within
  /// `safe_stop_linger` after kComponentErrorEvent (at once when no chart has a safe stop).
  ComponentError,
  UnhandledFault,  ///< a fault was injected and the task did not complete before the time limit
  SafeStop,        ///< a task chart entered its safe-stop state
  Interrupted,     ///< RunOptions::interrupt was set (Ctrl-C)
  PeerLost,        ///< a run split over hosts lost a peer; this host's charts stopped safely (or not: the reason says)
};
const char* toString(Outcome outcome);

/// A summary value of `run.summary` sampled during the run (e.g. one placement error per needle).
struct SummaryValue {
  std::string name;
  std::string unit;
  std::vector<double> values;  ///< in `unit`, one per sample
  std::vector<double> times;   ///< s
  std::string text;            ///< as the report shows it
};

/// The clearance of `run.clearance` over the run (its port read every step it is written).
struct ClearanceFigures {
  double threshold = 0.0;  ///< m
  /// m: the smallest clearance over the samples that count; +inf before any.
  double worst = std::numeric_limits<double>::infinity();
  double worst_at = 0.0;       ///< s
  std::string worst_state;     ///< every chart's state then
  double seconds_below = 0.0;  ///< s of samples at or under the threshold
  double seconds_sampled = 0.0;
  int unreachable = 0;  ///< NaN samples (the port's component could not measure the state)
  /// Per declared contact: its name and smallest distance [m] (0: touching or inside).
  std::vector<std::pair<std::string, double>> contacts;
  double last = std::numeric_limits<double>::quiet_NaN();  ///< m, the last sample (NaN: none, or paused)
  /// Per pair of groups of `run.clearance.pairs`: its smallest clearance over the samples that
  /// count (m; +inf before any), when and every chart's state then.
  struct Pair {
    std::string name;  ///< "micro/ur5"
    double worst = std::numeric_limits<double>::infinity();
    double worst_at = 0.0;  ///< s
    std::string worst_state;
  };
  std::vector<Pair> pairs;
};

/// How the real-time executor kept time (a run on the wall clock with the executor).
struct ExecutorFigures {
  bool ran = false;
  double period = 0.0;  ///< s, the tick
  std::string scheduler;  ///< "SCHED_FIFO priority 80", or what it fell back to
  bool memory_locked = false;
  std::uint64_t ticks = 0, deadline_misses = 0, worst_consecutive_misses = 0;
  double slipped = 0.0;  ///< s given up after stalls
  core::DurationFigures wake_latency;  ///< s after each deadline
  core::DurationFigures tick_compute;  ///< s per tick
  core::DurationFigures between_steps;  ///< s per tick outside the components' steps (switches)
  core::DurationFigures work_between_ticks;  ///< s per action, fault or input played between ticks
  std::vector<core::ComponentTiming> components;  ///< s per step, in the clock's order
  /// The components at their own pace: the oldest their hand-over got (s) against their max_age.
  std::vector<core::HandoverFigures> handovers;
  std::vector<std::string> warnings;
};

struct RunResult {
  Outcome outcome = Outcome::TimeLimit;
  std::string reason;  ///< one line: why the run ended (empty when completed)
  double duration = 0.0;  ///< s
  std::vector<EventRecord> events;
  /// What happened, in order, one line each: task states ("needle > root.WaitCryoCycle", a
  /// chart's folded leaves left out), switches ("needle deployment > NAME", "configuration > NAME"),
  /// every component's events ("NeedleMonitor: e_skin_touched"), safe stops ("needle safe stop")
  /// and faults ("fault faults.lua:3").
  std::vector<std::string> log;
  /// Every state (full path) each chart entered, in order of first entry, by chart name.
  std::map<std::string, std::vector<std::string>> states_entered;
  /// Each chart's active state (full path) when the run ended, in the order of run.charts.
  std::vector<std::pair<std::string, std::string>> final_states;
  std::vector<std::string> switches;  ///< "  12.345 s needle deployment NAME"
  /// Every observer's summary values (run.summary's first, in order; then those of other
  /// observers, e.g. a package's); the report shows each as a row.
  std::vector<SummaryValue> summary;
  std::vector<TrackingFigures> tracking;  ///< one per run.tracking entry, in order
  ClearanceFigures clearance;             ///< when run.clearance is declared
  ExecutorFigures executor;               ///< on the wall clock
  std::filesystem::path report;           ///< report.html, when a report folder was given

  bool completed() const { return outcome == Outcome::Completed; }
  /// The summary value called `name`. @throws std::out_of_range naming it.
  const SummaryValue& value(const std::string& name) const;
};

/// `cobra run`'s exit status for a run that ended: 0 completed, 3 a peer lost (a run split over
/// hosts), 1 otherwise (2 is `cobra run`'s for an application that does not load).
int exitStatus(const RunResult& result);
/// The line `cobra run` prints when the run ended: "completed in 163.400 s", else
/// "cobra run: SafeStop: <reason>" (on stderr).
std::string endLine(const RunResult& result);

/// "executor: 47039 ticks of 1.000 ms, SCHED_FIFO priority 80; 3 deadline misses ...": how the
/// executor kept time (cobra run prints it after a wall-clock run); "" when it did not run.
std::string executorLine(const ExecutorFigures& executor);

/// The entry file of `app`: `app` itself when it is a file, `app/<folder name>.lua` for a folder.
/// @throws std::runtime_error "apps/x: no entry file apps/x/x.lua (an application folder holds
///         <name>.lua)", or "apps/x: no such file or folder".
std::filesystem::path entryFile(const std::filesystem::path& app);

/// Loads, runs and reports one run.
/// @throws std::runtime_error (or core::Error) naming file:line for bad files: the deployment's
///         errors, a bad `run` table, a bad faults file.
RunResult runApp(const RunOptions& options);

}  // namespace cobra::run
