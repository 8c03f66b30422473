#pragma once
/// @file
/// Plain C++ mirrors of the thesis' Configurator tables (§3.2.2): `packages_list`,
/// `components_list`, `configuration_list`, `start_list`, `peers_list`, `activities_list`,
/// `connections_list`. Every entry carries the place it was written, so that every error can
/// say "file:line". The Lua loader fills these; tests and C++ programs may fill them directly.

#include <string>
#include <vector>

#include "cobra/core/activity.hpp"
#include "cobra/core/conn_policy.hpp"

namespace cobra::deploy {

/// Where an entry was written: a file and a 1-based line (0 when unknown).
struct SourceLocation {
  std::string file;
  int line = 0;

  /// "deploy.lua:12", "deploy.lua" without a line, "<no location>" when both are unknown.
  std::string text() const;
  friend bool operator==(const SourceLocation&, const SourceLocation&) = default;
};

/// One name in a list: an entry of `packages_list`, `configuration_list` or `start_list`.
struct NameEntry {
  std::string name;
  SourceLocation where;
};

/// `{ peer_name = "TrajGen", component_type = "CartesianTrajGen" }` of `components_list`.
struct ComponentSpec {
  std::string peer_name;
  std::string component_type;
  SourceLocation where;
};

/// `{ peer_name = "TaskSup", peers_to_add = { "MotPlan", "TrajGen" } }` of `peers_list`.
struct PeerSpec {
  std::string peer_name;
  std::vector<std::string> peers_to_add;
  SourceLocation where;
};

/// `{ peer_name = "TrajGen", period = 0.001, priority = 95, scheduler = "ORO_SCHED_RT" }` of
/// `activities_list`. A period of 0 means event-driven (steps on event-port data and operation
/// requests). `scheduler` accepts "ORO_SCHED_RT", "SCHED_FIFO", "fifo" (real-time) and
/// "ORO_SCHED_OTHER", "SCHED_OTHER", "other" (time-sharing), case-insensitively.
///
/// `own_pace = true`: on the wall clock (ClockMode::WallClock) the component runs on a thread of
/// its own beside the real-time executor instead of in its schedule, for work that cannot finish
/// within a period (a planner's search, network I/O): it hands over through ports, and what it
/// is asked (requests, event ports) is taken in its own thread. On the lockstep clock it steps in
/// the schedule like any other component, so both clocks run the same files.
///
/// `max_age = s` (own_pace only; default kDefaultMaxAge): how old what the component hands over
/// may get on the wall clock. A periodic own-pace component must end a step at least every
/// max_age; an event-driven one must answer each trigger (a request, new data on an event port)
/// within max_age of its arrival. The real-time executor checks it every tick and, past it, emits
/// `e_handover_stale_<component>` on the `Executor` component's events port (once per episode),
/// which a task chart can take; the run's report counts the episodes and the worst age.
struct ActivitySpec {
  std::string peer_name;
  double period = 0.0;  ///< s; 0 = event-driven
  int priority = 0;     ///< 1..99 for a real-time scheduler (0 is raised to 1, as RTT does)
  std::string scheduler = "ORO_SCHED_OTHER";
  SourceLocation where;
  bool own_pace = false;  ///< see above; after `where`, so `{name, period, priority, scheduler, where}` still reads
  double max_age = 0.0;   ///< s; own_pace only; 0: kDefaultMaxAge
  static constexpr double kDefaultMaxAge = 1.0;  ///< s: a search or an exchange answering within a second
  /// s: the bound the executor checks (max_age, or kDefaultMaxAge when not given).
  double handoverBound() const { return max_age > 0.0 ? max_age : kDefaultMaxAge; }

  /// Same period, priority and scheduler (the location does not matter).
  bool sameActivity(const ActivitySpec& other) const;
};

/// `setExecutor{ period = 0.001, priority = 80, cpu = 1, lock_memory = true, on_deadline_miss = "event",
/// safe_stop_after = 5 }`: how the real-time executor (core/realtime_executor.hpp) runs the
/// deployment on the wall clock. Ignored by the lockstep clock, which runs the same schedule in
/// simulated time. Setting it also makes the component `Executor`, whose `events` port carries
/// `e_deadline_missed` and `e_deadline_safe_stop` (connect it to the task supervisors).
struct ExecutorSpec {
  /// s: the tick; 0 = the greatest common divisor of the periodic components' periods.
  double period = 0.0;
  int priority = 80;  ///< SCHED_FIFO priority 1..99
  std::string scheduler = "SCHED_FIFO";
  int cpu = -1;  ///< the CPU the executor's thread is pinned to; -1: any
  bool lock_memory = true;  ///< mlockall at start
  /// "count" (misses are counted and reported) or "event" (also emits e_deadline_missed).
  std::string on_deadline_miss = "count";
  /// After this many consecutive misses the run ends in a safe stop (e_deadline_safe_stop); 0: never.
  int safe_stop_after = 0;
  SourceLocation where;
  bool declared = false;  ///< false: no setExecutor in the files (the defaults above apply)
};

/// `conn_policy = { type = "buffer", size = 8 }`. `type` is "data", "buffer" or "circular"
/// (case-insensitive; RTT's "DATA", "BUFFER", "CIRCULAR_BUFFER" are accepted too); `size` is
/// the number of samples kept and is ignored for data connections.
/// A connection between processes names a transport (core/transport.hpp), its topic and QoS:
/// `conn_policy = { type = "buffer", size = 16, transport = "dds", topic = "needle/events",
/// qos = { reliability = "reliable", depth = 16, lease = 0.1 } }`.
struct ConnPolicySpec {
  ConnPolicySpec() = default;
  ConnPolicySpec(std::string type_name, int samples) : type(std::move(type_name)), size(samples) {}

  std::string type = "data";
  int size = 1;
  std::string transport;  ///< "" in this process, else a registered transport ("dds")
  std::string topic;      ///< the transport's name of the connection
  /// `qos = { key = value }` in the order written, values as text ("16", "0.1", "reliable").
  std::vector<std::pair<std::string, std::string>> qos;
};

/// `{ output = "MotPlan.path", input = "TrajGen.path", conn_policy = cp }` of `connections_list`.
struct ConnectionSpec {
  std::string output;  ///< "Component.port" of an output port
  std::string input;   ///< "Component.port" of an input port
  ConnPolicySpec conn_policy;
  SourceLocation where;
};

/// The component and port names of "Component.port".
struct PortPath {
  std::string component;
  std::string port;
};

/// Splits "Component.port" at its first '.'.
/// @throws core::Error prefixed with `where` when there is no '.' or a side is empty.
PortPath parsePortPath(const std::string& text, const SourceLocation& where);

/// The core policy of `spec`. @throws core::Error prefixed with `where` on an unknown type, a
/// size below 1, an unknown transport (listing those registered), or a topic or QoS the transport
/// refuses (naming the key and the allowed values).
core::ConnPolicy toConnPolicy(const ConnPolicySpec& spec, const SourceLocation& where);

/// The core scheduler named by `name` (see ActivitySpec). @throws core::Error prefixed with
/// `where` listing the accepted names.
core::Scheduler toScheduler(const std::string& name, const SourceLocation& where);

}  // namespace cobra::deploy
