#pragma once
/// @file
/// The runtime half of cobra's statechart engine: a `Machine` runs one `Chart` (Model/Data).
/// Everything it needs is allocated at construction; `raise`, `step` and `run` allocate nothing,
/// take no lock and throw nothing (a callback that throws is reported to the observer, as rFSM
/// reports a failing Lua function, and the step goes on).
///
/// One `step()` is one pass of rFSM's `step` loop:
///  0. time events whose time has come are queued (active states from the leaf up to the root);
///  1. all queued events are taken: they are this step's events, used or not;
///  2. not yet entered: the path from root's `initial` is followed (entering states top-down);
///     the first step's events include `e_init_fsm`, queued by the constructor and `reset()`;
///  3. else with events: the active configuration is searched from the root down and the first
///     state (outermost first) with an enabled path takes it: one compound transition, through
///     connectors, each segment exiting up to the least common ancestor, running its effect and
///     entering down to its target. A transition is enabled when its guard (called first, as in
///     rFSM) does not say false and one of its events is among the step's (no events: any).
///     Every transition leaving a searched node has its guard asked, as rFSM collects all paths;
///  4. else (no events) the active leaf's `doo` runs once (resumed where it yielded).
/// rFSM's `step(fsm, n)` counts a pass whose events enabled nothing as no step; `EventsIgnored`
/// tells the caller so (script/'s rfsm.step does exactly that). `run()` steps until the machine is
/// idle: no events left and the `doo` idle, done or absent.
///
/// Deviation: rFSM checks time events after a step and queues them for the next one, so its
/// `run()` returns before handling them; cobra checks them before taking the step's events, so
/// the first step (or run) at which the deadline has passed handles them. Same order of events,
/// one step less of latency, which matters for a supervisor stepped once per update.
///
/// Events from `raise` wait in a queue of `queue_capacity`; events the engine raises itself
/// (`e_init_fsm`, `e_done@...`, time events) have their own reserve, so a flood of external
/// events can never make a chart miss its completion or its timeout.

#include <chrono>
#include <cstddef>
#include <functional>
#include <string_view>
#include <vector>

#include "cobra/statechart/chart.hpp"

namespace cobra::statechart {

/// Receives what a machine does, for traces and supervisors (called on the machine's thread).
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void entered(std::string_view /*fqn*/) {}
  virtual void exited(std::string_view /*fqn*/) {}
  virtual void transitionTaken(const Chart::Transition& /*transition*/) {}
  /// A step's events triggered no transition (they are dropped, as in rFSM).
  virtual void eventsIgnored(const StepEvents& /*events*/) {}
  /// A callback threw: `callback` is "entry", "exit", "doo", "guard" or "effect", `element` the
  /// state's fqn or the transition's text ("root.a -> root.b"), `what` the exception's message.
  virtual void callbackFailed(std::string_view /*callback*/, std::string_view /*element*/, std::string_view /*what*/) {}
};

enum class RaiseStatus { Queued, QueueFull, NameTooLong };

/// What one step did.
enum class StepResult {
  Entered,         ///< entered the chart through root's initial path
  Transitioned,    ///< took a compound transition
  EventsIgnored,   ///< had events, none enabled a transition (they are gone)
  DooRan,          ///< ran the active leaf's doo (busy)
  Idle,            ///< nothing to do: no events, doo idle, done or absent
  CannotEnter,     ///< no enabled path from root's initial connector
};

class Machine {
 public:
  /// Longest event name kept (longer ones are refused by raise).
  static constexpr std::size_t kMaxEventName = 95;

  /// `clock` gives the time of time events (e.g. the component's clock, so that the lockstep
  /// clock drives them). `queue_capacity` bounds the events waiting for a step.
  Machine(const Chart& chart, std::function<std::chrono::nanoseconds()> clock, std::size_t queue_capacity = 64);

  /// Queues an event for the next step. Real-time safe.
  RaiseStatus raise(std::string_view event) noexcept;
  StepResult step() noexcept;
  /// Steps until idle or `max_steps` steps; returns true when idle.
  bool run(std::size_t max_steps = 10000) noexcept;
  /// Back to not entered, with no events (the next step enters through root's initial).
  void reset() noexcept;

  /// Fully qualified name of the active leaf, "" before entry.
  std::string_view activeLeaf() const noexcept;
  /// True when the state `fqn` is active.
  bool isActive(std::string_view fqn) const noexcept;
  bool entered() const noexcept { return entered_; }
  std::size_t queuedEvents() const noexcept { return queue_size_; }
  const Chart& chart() const noexcept { return *chart_; }
  void setObserver(Observer* observer) noexcept { observer_ = observer; }

 private:
  struct QueuedEvent {
    EventId id;
    std::size_t length;
    char text[kMaxEventName];
  };
  /// e_init_fsm, e_done@..., time events: they use the queue's reserve, so they are never lost.
  void raiseInternal(EventId id, std::string_view name) noexcept;
  void push(EventId id, std::string_view name) noexcept;
  void checkTimeEvents() noexcept;
  bool enabled(const Chart::Transition& t, const StepEvents& events) noexcept;
  /// Finds the first enabled path from `node` into path_ (transition indices); true if found.
  /// Evaluates every transition leaving `node` (guards included, as rFSM does) and, when
  /// `record`, writes the first enabled complete path into path_ from `depth` on.
  bool findPath(int node, const StepEvents& events, std::size_t depth, bool record) noexcept;
  void executePath(const StepEvents& events) noexcept;
  void execute(const Chart::Transition& t, const StepEvents& events) noexcept;
  void enter(int node) noexcept;
  void exit(int node) noexcept;
  int lca(int a, int b) const noexcept;
  /// Calls a user callback; one that throws is reported to the observer: returns false then.
  template <class Callback>
  bool guarded(const char* callback, std::string_view element, Callback&& call) noexcept;
  void failed(const char* callback, std::string_view element, const char* what) noexcept;

  const Chart* chart_;
  std::function<std::chrono::nanoseconds()> clock_;
  std::size_t capacity_;  // events raise() may queue between two steps
  Observer* observer_ = nullptr;
  bool entered_ = false;
  int active_leaf_ = -1;
  std::vector<int> active_child_;                  // per node, -1 none
  std::vector<char> leaf_done_;                    // per node: doo finished (or none)
  std::vector<char> doo_restart_;                  // per node: next doo call restarts
  std::vector<std::chrono::nanoseconds> entry_time_;  // per node
  std::vector<char> time_fired_;                   // per transition
  // Per node: whether it or an ancestor has a time transition (most leaves have none, and
  // checkTimeEvents runs every step: it returns at once for them).
  std::vector<char> timed_path_;
  std::vector<QueuedEvent> queue_;                 // events for the next step, from index 0
  std::size_t queue_size_ = 0, internal_queued_ = 0;
  std::vector<QueuedEvent> current_;               // this step's events (swapped with queue_)
  std::vector<StepEvents::Entry> current_entries_;
  std::vector<int> path_, down_;                   // workspaces (size: nodes)
  std::size_t path_length_ = 0;
};

}  // namespace cobra::statechart
