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
struct ActivitySpec {
  std::string peer_name;
  double period = 0.0;  ///< s; 0 = event-driven
  int priority = 0;     ///< 1..99 for a real-time scheduler (0 is raised to 1, as RTT does)
  std::string scheduler = "ORO_SCHED_OTHER";
  SourceLocation where;

  /// Same period, priority and scheduler (the location does not matter).
  bool sameActivity(const ActivitySpec& other) const;
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
