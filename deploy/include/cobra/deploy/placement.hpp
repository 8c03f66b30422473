#pragma once
/// @file
/// Placement: one application split over processes or hosts (thesis §4.4: each robot controller
/// on its own computer). The same application files run in every process; the placement says
/// which components live on which host, and each process is told its own host
/// (`cobra run APP --host NAME`, ConfiguratorOptions::host). In Lua, the entry file declares it
/// before its first `initConfigurator`:
/// @code
/// placement = {
///   hosts = { needle = { "ISUR", "Patient", "Needle*" }, probe = { "UR5", "Probe*" } },
///   everywhere = { "Link" },        -- one instance on every host (the DDS link, DdsLink)
///   transport = "dds",              -- carries the connections between hosts (default "dds")
///   qos = { reliability = "reliable" },  -- added to each of them (the transport's keys)
/// }
/// @endcode
/// A pattern is a component name, or a prefix followed by `*`. Every component must match the
/// patterns of exactly one host, or of `everywhere`. Without a host the placement is ignored and
/// everything runs in one process.

#include <string>
#include <utility>
#include <vector>

#include "cobra/core/conn_policy.hpp"
#include "cobra/deploy/spec.hpp"

namespace cobra::deploy {

/// The `placement` table.
struct PlacementSpec {
  struct Host {
    std::string name;
    std::vector<std::string> patterns;  ///< component names, or prefixes ending in '*'
    SourceLocation where;
  };
  std::vector<Host> hosts;
  std::vector<std::string> everywhere;  ///< patterns of the components every host runs
  std::string transport = "dds";        ///< the transport of the connections between hosts
  /// Transport options (QoS) added to every connection between hosts, key and text value.
  std::vector<std::pair<std::string, std::string>> qos;
  SourceLocation where;
};

/// A placement in force in one process: its host and the sites of the components.
class Placement {
 public:
  /// Where a component runs, seen from this process.
  enum class Site {
    Local,       ///< on this process's host: created and run here
    Remote,      ///< on another host: its ports are known (for checks), nothing of it runs here
    Everywhere,  ///< one instance on every host (the DDS link): local, its connections stay local
  };

  /// @throws core::Error "file:line: ..." when the placement has no host, `host` is not one of
  /// its hosts (listing them), or a pattern is empty or has a '*' other than last.
  Placement(PlacementSpec spec, std::string host);

  const std::string& host() const { return host_; }
  const PlacementSpec& spec() const { return spec_; }

  /// The host of `component` ("" for an `everywhere` one).
  /// @throws core::Error "<where>: component 'X' is placed on no host ..." or "... on two hosts
  /// (a at file:line, b at file:line)", naming the placement.
  std::string hostOf(const std::string& component, const SourceLocation& where) const;
  /// The site of `component`. @throws as hostOf.
  Site siteOf(const std::string& component, const SourceLocation& where) const;

  /// The policy of a connection between hosts whose output port is `output` ("Component.port"):
  /// `local`'s type and size, the placement's transport and QoS, topic "Component/port".
  core::ConnPolicy crossHostPolicy(const core::ConnPolicy& local, const std::string& output) const;

 private:
  PlacementSpec spec_;
  std::string host_;
};

/// True when `name` matches `pattern` (equal, or starting with the part before a trailing '*').
bool matchesPlacementPattern(const std::string& pattern, const std::string& name);

}  // namespace cobra::deploy
