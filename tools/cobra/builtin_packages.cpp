#include "builtin_packages.hpp"

#include "cobra/bridges/package.hpp"
#include "cobra/components/control/package.hpp"
#include "cobra/components/coordination/package.hpp"
#include "cobra/components/drivers/package.hpp"
#include "cobra/components/motion/package.hpp"
#include "cobra/components/sim/package.hpp"
#include "cobra/components/planning/package.hpp"

namespace cobra::tools {

void addBuiltinPackages(deploy::Configurator& configurator) {
  configurator.packages().addBuiltin("cobra_motion", components::registerMotionPackage);
  configurator.packages().addBuiltin("cobra_coordination", components::registerCoordinationPackage);
  configurator.packages().addBuiltin("cobra_control", components::registerControlPackage);
  configurator.packages().addBuiltin("cobra_bridges", bridges::registerBridgesPackage);
  configurator.packages().addBuiltin("cobra_drivers", components::registerDriversPackage);
  configurator.packages().addBuiltin("cobra_sim", components::registerSimPackage);
  configurator.packages().addBuiltin("cobra_planning", components::registerPlanningPackage);
}

}  // namespace cobra::tools
