#include "cobra/components/monitoring/package.hpp"

#include "cobra/components/monitoring/contact_monitor.hpp"
#include "cobra/components/monitoring/needle_insertion_monitor.hpp"
#include "cobra/components/monitoring/ultrasound_monitor.hpp"

namespace cobra::components {

void registerMonitoringPackage(deploy::PackageBuilder& package) {
  package
      .component<NeedleInsertionMonitor>("NeedleInsertionMonitor",
                                         "needle insertion events from the measured wrench and pose")
      .component<UltrasoundMonitor>("UltrasoundMonitor", "ultrasound visibility and probe contact events")
      .component<ContactMonitor>("ContactMonitor", "contact made / lost, off / on the nominal path, force over its limit");
}

}  // namespace cobra::components
