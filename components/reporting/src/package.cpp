#include "cobra/components/reporting/package.hpp"

#include "cobra/deploy/configurator.hpp"

namespace cobra::components {

bool PeerReporter::configureHook() {
  if (!peers_reported_ && state() == core::State::PreOperational) {
    deploy::Configurator* configurator = this->configurator();
    const std::vector<std::string> none;
    const std::vector<std::string>& peers = configurator != nullptr ? configurator->peersOf(name()) : none;
    if (peers.empty())
      return core::Component::refuse("no ports to report: add the components to record as its peers "
                    "(peers_list = { { peer_name = \"" + name() + "\", peers_to_add = { ... } } })");
    try {
      for (const std::string& peer : peers) reportComponent(configurator->getReferences().get(peer));
    } catch (const core::Error& e) {
      return core::Component::refuse(e.what());
    }
    peers_reported_ = true;
  }
  return Reporter::configureHook();
}

void registerReportingPackage(deploy::PackageBuilder& package) {
  package.component<PeerReporter>(
      "Reporter", "records the output ports of its peers to a CSV file without blocking their writers (OCL FileReporting)");
}

}  // namespace cobra::components
