#include "cobra/components/coordination/package.hpp"

#include "cobra/components/coordination/supervisor.hpp"

namespace cobra::components {

void registerCoordinationPackage(deploy::PackageBuilder& package) {
  package.component<Supervisor>("Supervisor", "runs an rFSM chart: task, deployment or configuration supervisor");
}

}  // namespace cobra::components
