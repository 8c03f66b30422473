#pragma once
/// @file
/// The immutable half of cobra's statechart engine (Model/Data split, ARCHITECTURE §8): a `Chart`
/// built and checked once by a `ChartBuilder`, then run by any number of `Machine`s.
///
/// The semantics are rFSM's (github.com/kmarkus/rFSM, thesis §3.1.3), rule for rule:
/// - a state with sub-nodes (states or connectors) is composite, else a leaf; `doo` only on leaves;
/// - transitions have `src`, `tgt`, `events` (any of them triggers; none = any event), `guard`,
///   `effect` and a priority number `pn` (higher first);
/// - paths: a name without dots is a node of the scope the transition is defined in; a leading
///   dot is relative to that scope (".a.b"); anything else is absolute ("root.a.b", or "a.b"
///   which rFSM also reads from the root);
/// - a target that is composite means its `initial` connector; an `initial` connector is created
///   when a transition of the scope leaves from it; the root must have one. Transitions from
///   `initial` may have events and guards (rFSM's README dispatches from `initial` on
///   e_sw_err/e_hw_err): they are matched against the events of the step that enters;
/// - `e_done` in a transition's events means `e_done@<fqn of its source>`, raised when a leaf
///   without `doo` is entered, or when its `doo` finishes;
/// - `e_after(t)` (t in s) fires once strictly more than t has passed on the machine's clock
///   since the source state was entered, `e_at(t)` once the clock reads strictly more than t (s
///   since the clock's epoch); they become the events `e_after(t)@<fqn of src>` and
///   `e_at(t)@<fqn of src>`, t printed as Lua prints tonumber(t) ("e_after(1.50)" waits for
///   "e_after(1.5)@root.a"), and raising that name by hand triggers them too, as in rFSM.
///
/// Where cobra is stricter or more determined than rFSM, and why:
/// - equal `pn`s keep the order the transitions were added in (rFSM's table.sort is not stable,
///   so its order is unspecified): the same chart always behaves the same;
/// - `e_done` or a time event on a transition leaving a connector is a load error: a connector
///   is never entered nor completes, so rFSM would wait forever (or fail at run time);
/// - a state named `initial` is refused: rFSM requires `initial` to be a connector;
/// - each time event of a state has its own timer (rFSM keeps only the last one per state);
/// - `internal` targets and event predicates (functions in `events`) are not supported (rFSM
///   refuses the first; use a guard for the second).
/// See machine.hpp for how a step runs.

#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace cobra::statechart {

/// An interned event name. Names no transition mentions have id `kUnknownEvent`.
using EventId = std::uint32_t;
inline constexpr EventId kUnknownEvent = 0xffffffffU;

/// The events a step processes, as guards and effects see them.
class StepEvents {
 public:
  struct Entry {
    EventId id;
    std::string_view name;
  };
  explicit StepEvents(std::span<const Entry> entries) : entries_(entries) {}
  std::size_t size() const noexcept { return entries_.size(); }
  bool empty() const noexcept { return entries_.empty(); }
  std::string_view name(std::size_t i) const noexcept { return entries_[i].name; }
  EventId id(std::size_t i) const noexcept { return entries_[i].id; }
  bool contains(std::string_view name) const noexcept;

 private:
  std::span<const Entry> entries_;
};

/// What a `doo` reports after running a slice of its work (rFSM: `rfsm.yield(true)` is Idle).
enum class DooStatus { Busy, Idle, Done };

/// Callbacks run by the machine's thread. Calling a stored std::function never allocates.
using Action = std::function<void()>;
using Guard = std::function<bool(const StepEvents&)>;
using Effect = std::function<void(const StepEvents&)>;
/// `restart` is true on the first call after each entry of its state: start from the beginning.
using Doo = std::function<DooStatus(bool restart)>;

/// A state's callbacks (all optional). `origin` ("file.lua:12") prefixes its load-time errors.
struct StateSpec {
  Action entry;
  Action exit;
  Doo doo;
  std::string origin;
};

/// A transition as written: `src`/`tgt` are paths resolved in the scope it is added to.
struct TransitionSpec {
  std::string src;
  std::string tgt;
  std::vector<std::string> events;
  int pn = 0;
  Guard guard;
  Effect effect;
  std::string origin;
};

enum class NodeKind : std::uint8_t { State, Connector };

/// The built chart. Indices are stable; node 0 is the root.
class Chart {
 public:
  struct Node {
    NodeKind kind;
    std::string name;
    std::string fqn;  ///< "root", "root.a.b"
    int parent;       ///< the root is its own parent
    int depth;        ///< the root is 0
    bool composite;   ///< has sub-nodes (states or connectors)
    int initial;      ///< its `initial` connector, or -1
    std::vector<int> transitions;  ///< outgoing, by pn (higher first), then in the order added
    StateSpec callbacks;
    EventId done_event;  ///< e_done@fqn (leaves)
  };
  struct Transition {
    int src;
    int tgt;  ///< a leaf state or a connector: a composite target is its initial connector
    std::vector<EventId> events;  ///< sorted; empty = any event
    int pn;
    Guard guard;
    Effect effect;
    std::string origin;
    std::string text;  ///< "root.a -> root.b", for traces and errors
    double time_spec;  ///< s, for a time event; < 0 otherwise
    bool time_absolute;
    EventId time_event;
  };

  const std::vector<Node>& nodes() const noexcept { return nodes_; }
  const std::vector<Transition>& transitions() const noexcept { return transitions_; }
  const Node& node(int index) const { return nodes_.at(static_cast<std::size_t>(index)); }
  /// The node with this fully qualified name, or -1.
  int find(std::string_view fqn) const noexcept;
  /// The id of an event name, or kUnknownEvent. No allocation.
  EventId eventId(std::string_view name) const noexcept;
  /// Every event name some transition waits for (including e_done@... and time events).
  const std::vector<std::string>& eventNames() const noexcept { return event_names_; }

 private:
  friend class ChartBuilder;
  std::vector<Node> nodes_;
  std::vector<Transition> transitions_;
  std::vector<std::string> event_names_;            // by id
  std::vector<std::pair<std::string, EventId>> by_name_;  // sorted, for lookups without allocation
};

/// Builds a Chart, then checks it as a whole. Configure time: allocates, throws.
class ChartBuilder {
 public:
  ChartBuilder();
  /// The root's callbacks (rFSM allows entry/exit on the root).
  void setRootCallbacks(StateSpec callbacks);
  /// Adds state `name` under the node `parent_fqn` ("root", "root.a"). Composite or leaf is
  /// decided when the chart is built. @throws std::invalid_argument for an unknown parent, a
  /// duplicate or empty name, or a name with a dot.
  void addState(std::string_view parent_fqn, std::string name, StateSpec spec = {});
  void addConnector(std::string_view parent_fqn, std::string name, std::string origin = {});
  /// Adds a transition defined in the scope `scope_fqn`; its paths are resolved at build().
  void addTransition(std::string_view scope_fqn, TransitionSpec spec);

  /// Resolves and checks everything; the builder is left empty.
  /// @throws std::invalid_argument with one line per problem, each naming the origin (file:line
  /// when given), the element's path and what to do.
  Chart build();

 private:
  struct PendingTransition {
    int scope;
    TransitionSpec spec;
  };
  int lookup(std::string_view fqn) const;
  /// "; the nodes of root.a are root.a.x, root.a.y": what exists where `missing_fqn` was looked for.
  std::string nodesNear(std::string_view missing_fqn) const;
  int addNode(std::string_view parent_fqn, std::string name, NodeKind kind, StateSpec spec);

  Chart chart_;
  std::vector<PendingTransition> pending_;
};

}  // namespace cobra::statechart
