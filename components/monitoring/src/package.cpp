#include "cobra/components/monitoring/package.hpp"

#include "cobra/components/monitoring/needle_insertion_monitor.hpp"
#include "cobra/components/monitoring/ultrasound_monitor.hpp"

namespace cobra::components {

void registerMonitoringPackage(deploy::PackageBuilder& package) {
  package
      .component<NeedleInsertionMonitor>("NeedleInsertionMonitor",
                                         "needle insertion events from the measured wrench and pose")
      .component<UltrasoundMonitor>("UltrasoundMonitor", "ultrasound visibility and probe contact events");
}

}  // namespace cobra::components
