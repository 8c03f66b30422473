#pragma once
// One run of an application (runner.hpp: runApp): the deployment loaded from its entry file, its
// charts, actions and faults armed, the observers of its `run` table's sections attached
// (observer.hpp), then one observation per step until the run ends. Private to cobra::run.

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "cobra/core/realtime_executor.hpp"
#include "cobra/deploy/deploy.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/run/observer.hpp"
#include "cobra/run/port_tap.hpp"
#include "cobra/run/report.hpp"
#include "cobra/run/run_spec.hpp"
#include "cobra/run/runner.hpp"
#include "builtin_observers.hpp"
#include "remote_entries.hpp"
#include "stall_watch.hpp"

namespace cobra::components {
class Supervisor;
}

namespace cobra::run {

// `state` without its last component when that is one of `fold` (the run table's `fold`: leaves
// such as Moving shown as their parent).
std::string foldState(const std::string& state, const std::vector<std::string>& fold);

// A chart of `run.charts`: on the lockstep clock its supervisor's active state, read between two
// instants; in real time its taskState port (the supervisor's thread writes it; the state before
// the runner connected shows once the chart changes state).
// (ChartState: its spec, its full path now and one step before, changed: they differ, or the first step.)
struct Chart : ChartState {
  const components::Supervisor* supervisor = nullptr;
  std::unique_ptr<Tap<core::TaskState>> state_tap;
  std::string shown;                   // folded, as last logged
  std::string lane;                    // its timeline lane: "NAME chart"
  const char* leaf = nullptr;          // lockstep: the supervisor's active leaf string `state` copies
  std::string last_failure;            // "Source: event at t s"
  StallWatch stall;                    // what it waits for in its state, and heard there
};

// An action or fault armed by its trigger.
struct Armed {
  ActionSpec spec;
  bool fault = false;
  double due = -1.0;  // s; < 0: not triggered yet
  int fired = 0;
  std::mt19937 random{spec.seed};  // draws spec.chance
};

// Hears every component's lifecycle state changes (core::StateListener): a change to Exception
// or FatalError counts, on whatever thread made it, and the run looks at the components' states
// only after one (instead of polling each component every step). It owns its registrations: its
// destructor leaves the components it listens to that still exist, so a Session member declared
// after the configurator (whose destructor stops the components) leaves them before they die,
// also when the Session's constructor throws after listenTo (no ~Session then).
class ComponentErrors final : public core::StateListener {
 public:
  explicit ComponentErrors(core::ComponentRegistry& refs) : refs_(refs) {}
  ComponentErrors(const ComponentErrors&) = delete;
  ComponentErrors& operator=(const ComponentErrors&) = delete;
  ~ComponentErrors() { leave(); }

  // Listens to the registry's components now: those a switch removed are gone (their listener
  // slots with them); a listener is added once per component.
  void listenToAll() {
    listened_ = refs_.components();
    for (core::Component* c : listened_) c->addStateListener(*this);
  }
  void stateChanged(const core::Component&, core::State, core::State to) noexcept override {
    if (to == core::State::Exception || to == core::State::FatalError) count_.fetch_add(1, std::memory_order_release);
  }
  std::uint64_t count() const { return count_.load(std::memory_order_acquire); }

 private:
  // Leaves every listened component still in the registry (one a switch removed is destroyed).
  void leave() noexcept {
    for (core::Component* c : refs_.components())
      if (std::find(listened_.begin(), listened_.end(), c) != listened_.end()) c->removeStateListener(*this);
    listened_.clear();
  }

  core::ComponentRegistry& refs_;
  std::vector<core::Component*> listened_;  // the components it listens to
  std::atomic<std::uint64_t> count_{0};
};

// The runner's own rows of the report: the executor's timing (wall clock): ticks, misses,
// latency, compute, the `components` slowest, the hand-overs.
std::vector<std::pair<std::string, std::string>> executorRows(const ExecutorFigures& executor, std::size_t components);
// "median 3.1 us, p99 ..., worst ... (n samples)".
std::string executorTimingText(const core::DurationFigures& figures);

class Session {
 public:
  // Loads the application and attaches everything. @throws as runApp.
  Session(const RunOptions& options, std::filesystem::path entry);
  /// The executor goes before the configurator (members in reverse order): the configurator
  /// stops asking it to watch hand-overs first.
  ~Session();
  // Steps until the run ends, then fills the result and writes the run folder.
  RunResult run();

 private:
  // Setup: each checks the names it is given against the deployment.
  void attachCharts();
  void armActions();
  void attachEventLog();
  // The observers of the run table's sections (spec_.observers), in the registry's order.
  void attachObservers();
  // Listens to every component's state (again after a switch: a deployment may bring its own).
  void listenToComponents();
  void attachObserver();
  // One step.
  void advance();
  // True when a chart's state was read anew (the wall clock: one change per chart and call).
  bool observeCharts();
  // Wall clock: the chart states left waiting after an observation, taken in turn; true when it
  // took one (which the observer has not seen yet).
  bool catchUpStates();
  // The observer's step: the run's time, chart states, deployments, configurations, clearance.
  void showToObserver();
  void readEvents();
  void observeSwitches();
  // The scopes whose configuration `name` is now (sets a component of their deployment; all when none).
  void assignConfiguration(const std::string& name);
  // Every observer's step (`full`: a whole observation; false: a catch-up round of chart states).
  void stepObservers(bool full, bool records);
  void playActions();
  // Plays an action's (or input's) Lua table, between two ticks of the executor on the wall
  // clock (as between two instants of the lockstep clock). @throws naming its file:line and the time.
  void play(const ActionSpec& action);
  void playNow(const ActionSpec& action);
  // Wall clock: runs the executor and observes from this thread every run step until the end.
  void runOnTheWallClock(std::chrono::nanoseconds step);
  void noteExecutorFigures();
  // True when the run ends after this step: decided, and watched for RunOptions::watch_after_end.
  bool ended();
  // True when the run's outcome is decided by this step (sets the outcome and reason).
  bool decide();
  void noteSafeStop(const Chart& chart);
  // A component newly in Exception or FatalError (`text`: "component 'X' is in Exception: ...").
  // True when the run ends with it at once: no chart has a safe stop to react with. Otherwise the
  // charts are told (e_component_error, kComponentError) and the run waits for their safe stop.
  bool noteComponentError(const core::Component& component, const std::string& text);
  // An event that may be a safe stop's reason: the run table's `failures`, and every refused
  // switch (e_configure_failed_*, e_deploy_failed_*).
  bool isFailure(const std::string& event) const;
  // After the run.
  void writeReport(const std::vector<std::string>& observer_files);

  // Split over hosts (RunOptions::host): drops the run table's entries of other hosts' components.
  void dropOtherHostsEntries();
  // This host's charts ended: tells the peers (once); true while they have not all ended.
  bool peersHoldTheRun();
  // Notes the first loss of a peer (the sync gave up on it).
  void notePeerLoss();
  // Notes the peers the link has heard from ("peer joined: 'probe'"), every 100 steps.
  void notePeerJoins();

  Chart* chartOf(const std::string& name);
  Chart& chartForSource(const std::string& source);
  std::string statesText() const;
  void say(const std::string& what) const;

  const RunOptions& options_;
  std::filesystem::path entry_;
  deploy::Configurator configurator_;
  script::LuaState lua_;
  deploy::LuaDeployer deployer_;
  RunSpec spec_;
  core::ComponentRegistry& refs_;

  std::vector<Chart> charts_;
  std::vector<Armed> armed_;
  struct EventTap {
    std::string source;                           // the component
    std::unique_ptr<core::InputPortBase> reader;  // connected to its events/outputEvents port
    core::InputPort<core::Event>* events;         // reader as an event port (nullptr: another type)
  };
  std::vector<EventTap> event_taps_;
  // Set by every event tap of type Event when an event arrives (PortBase::setNewDataFlag): the
  // taps are read only then, not polled at every step. Taps of another type are polled.
  std::atomic<bool> new_events_{true};
  Recording recording_;
  std::vector<const ChartState*> chart_states_;  // charts_ as the observers see them
  std::unique_ptr<ObserverContext> context_;
  std::vector<Observer*> observers_;  // spec_.observers', in order
  // After configurator_: destroyed before it, it leaves the components before they are stopped.
  ComponentErrors component_errors_{refs_};
  std::uint64_t component_errors_seen_ = UINT64_MAX;  // component_errors_.count() when last looked (max: look)
  // The components already found in Exception / FatalError (each is told to the charts once).
  std::vector<const core::Component*> errors_noted_;
  // Writes e_component_error (its source: the component in error) into every chart's supervisor's
  // inputEvents; nullptr when no chart of run.charts has a safe stop (the run then ends at once).
  std::unique_ptr<core::OutputPort<core::Event>> component_error_events_;
  double component_error_at_ = -1.0;  // s; < 0: no component error told to the charts
  std::string component_error_;       // the first one: "component 'X' is in Exception: ..."
  std::vector<std::string> scopes_, shown_deployment_;
  std::string shown_configuration_;
  std::vector<std::string> scope_configuration_;  // per scope: the configuration in force (StepView)
  std::vector<std::string> timeline_configuration_;  // per scope: what its "configuration" row shows
  // Lockstep clock: every Supervisor with the configuration it last had applied, as last seen
  // (two applied in one step are both seen; Configurator::currentConfiguration keeps the last only).
  std::vector<std::pair<const components::Supervisor*, std::string>> switchers_;
  /// Configurator::switchCount() when observeSwitches last looked (max: never): the same count,
  /// the same deployments and configuration (looked up in maps otherwise).
  std::uint64_t switches_seen_ = UINT64_MAX;
  std::vector<core::Component*> components_;
  TimelineRecorder timeline_;
  RunResult result_;
  // The observer's view (options_.observer): pointers into charts_.
  std::vector<ActionSpec> inputs_;  // run.studio.inputs as calls
  std::vector<const std::string*> view_states_;

  double t_ = 0.0;  // s
  // s since the previous observation: the step on the lockstep clock; on the wall clock what
  // passed (an observation may come late), so time-weighted figures stay time-weighted.
  double dt_ = 0.0;
  long steps_ = 0;
  long record_every_ = 1;
  double next_progress_ = 0.0;
  double safe_stop_at_ = -1.0;
  double decided_at_ = -1.0;  // s; < 0: the outcome is not decided yet
  // Split over hosts.
  RemoteHostOf remote_host_;  // empty without a placement
  RemoteEntries remote_entries_;
  bool told_done_ = false;
  double peer_lost_at_ = -1.0;  // s; < 0: no peer lost
  std::string lost_peers_;      // "peer 'probe' lost at 12.345 s"
  std::vector<std::string> joined_peers_;  // as noted
  // The wall clock's executor (RunOptions::realtime without thread_per_component); made at
  // setup so that a bad setExecutor is reported before anything moves.
  std::unique_ptr<core::RealtimeExecutor> executor_;
  std::vector<std::string> catch_up_previous_;  // catchUpStates: each chart's previous state
};

}  // namespace cobra::run
