#include "cobra/components/builtin_packages.hpp"

#include "cobra/bridges/package.hpp"
#include "cobra/components/control/package.hpp"
#include "cobra/components/coordination/package.hpp"
#include "cobra/components/drivers/package.hpp"
#include "cobra/components/monitoring/package.hpp"
#include "cobra/components/motion/package.hpp"
#include "cobra/components/planning/package.hpp"
#include "cobra/components/reporting/package.hpp"
#include "cobra/components/signal/package.hpp"
#include "cobra/components/sim/package.hpp"
#include "cobra/components/task/package.hpp"

namespace cobra::components {

void addBuiltinPackages(deploy::PackageRegistry& packages) {
  packages.addBuiltin("cobra_signal", registerSignalPackage);
  packages.addBuiltin("cobra_motion", registerMotionPackage);
  packages.addBuiltin("cobra_task", registerTaskPackage);
  packages.addBuiltin("cobra_coordination", registerCoordinationPackage);
  packages.addBuiltin("cobra_control", registerControlPackage);
  packages.addBuiltin("cobra_planning", registerPlanningPackage);
  packages.addBuiltin("cobra_bridges", bridges::registerBridgesPackage);
  packages.addBuiltin("cobra_drivers", registerDriversPackage);
  packages.addBuiltin("cobra_sim", registerSimPackage);
  packages.addBuiltin("cobra_monitoring", registerMonitoringPackage);
  packages.addBuiltin("cobra_reporting", registerReportingPackage);
}

}  // namespace cobra::components
