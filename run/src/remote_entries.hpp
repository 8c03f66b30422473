#pragma once
// One application split over hosts (deploy/placement.hpp): each host's run observes only its own
// components. Drops from a run's `run` table the entries that name another host's components,
// and those that depend on a dropped chart or tracking. Private to cobra::run.

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "cobra/run/run_spec.hpp"

namespace cobra::run {

/// The host of a component when it is another host's, "" when it runs in this process.
using RemoteHostOf = std::function<std::string(const std::string& component)>;

/// The component of a port, member or column path: "Robot" of "Robot.measCartPose.z".
std::string componentOfPath(const std::string& path);

/// What dropRemoteEntries dropped.
struct RemoteEntries {
  /// Per other host, its dropped entries as the run table names them ("run.charts 'us'",
  /// "run.tracking 'UR5 probe'"), in the table's order.
  std::map<std::string, std::vector<std::string>> by_host;
  std::map<std::string, std::string> charts;  ///< dropped chart -> its host
};

/// Removes the entries of `spec` (charts, actions, record ports, plots, summary values, tracking,
/// clearance and its contacts, studio entries) naming a component of another host, or a chart or
/// tracking dropped so.
RemoteEntries dropRemoteEntries(RunSpec& spec, const RemoteHostOf& remote_host);

/// The host `action` (a run.actions entry or a fault) belongs to when it is not this process's:
/// it calls, writes or sets a remote component, or waits for a state of a chart of `dropped`.
/// "" otherwise.
std::string remoteHostOfAction(const ActionSpec& action, const RemoteEntries& dropped, const RemoteHostOf& remote_host);

}  // namespace cobra::run
