#include "cobra/components/reporting/package.hpp"

#include <cstdio>
#include <string>

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
      // Each peer's output ports, as OCL's FileReporting records its peers'; a port whose length
      // its type does not give (a vector) cannot be given columns here: it is left out and said
      // once, with how to record it.
      for (const std::string& peer : peers) {
        std::string left_out;
        reportComponent(configurator->getReferences().get(peer), false, &left_out);
        if (!left_out.empty())
          std::fprintf(stderr,
                       "[cobra] Reporter '%s': not recorded: %s: its length is not part of its type; record it with "
                       "reportPort(port, number of elements)\n",
                       name().c_str(), left_out.c_str());
      }
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
