#pragma once
/// @file
/// The "cobra_reporting" package: the Reporter as a deployable component type (thesis §3.2.2's
/// listing: OCL::FileReporting), recording the ports of its peers.

#include <string>

#include "cobra/components/reporting/reporter.hpp"
#include "cobra/deploy/configurator_client.hpp"
#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

/// The Reporter a deployment file makes by type name ("Reporter"): at its first configure it
/// records every output port (events excluded) of each of its peers, in the order of
/// `peers_list` (`{ peer_name = "Reporter", peers_to_add = { "MotPlan" } }`), as OCL's
/// FileReporting reports its peers. A peer with a vector or JntArray output (whose length the
/// Reporter needs) refuses the configuration naming the port: report such components from C++
/// with reportPort(port, n). Without peers the configuration is refused, saying so.
class PeerReporter : public Reporter, public deploy::ConfiguratorClient {
 public:
  explicit PeerReporter(std::string name) : Reporter(std::move(name)) {}

 protected:
  bool configureHook() override;
  void onRequestDone(const deploy::SwitchRequest&, bool, std::string_view) override {}

 private:
  bool peers_reported_ = false;
};

/// Registers "Reporter" (PeerReporter).
void registerReportingPackage(deploy::PackageBuilder& package);

}  // namespace cobra::components
