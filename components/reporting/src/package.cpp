#include "cobra/components/reporting/package.hpp"

#include <cstdio>
#include <string>

#include "cobra/core/port.hpp"
#include "cobra/deploy/configurator.hpp"
#include "source.hpp"

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
        core::Component& component = configurator->getReferences().get(peer);
        std::string left_out;
        std::size_t chosen = 0;
        for (core::PortBase* port : component.ports()) {
          if (port->direction() != core::PortDirection::Output || port == &component.events()) continue;
          if (reporting_detail::needsLength(port->type())) {
            left_out += (left_out.empty() ? "" : ", ") + peer + "." + port->name() + " (" +
                        std::string(port->type().name) + ")";
            continue;
          }
          reportPort(*port);
          ++chosen;
        }
        if (!left_out.empty())
          std::fprintf(stderr,
                       "[cobra] Reporter '%s': not recorded: %s: its length is not part of its type; record it with "
                       "reportPort(port, number of elements)\n",
                       name().c_str(), left_out.c_str());
        if (chosen == 0) reportComponent(component);  // says why nothing of it can be recorded
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
