#include "cobra/bridges/package.hpp"

#include "cobra/bridges/isur_robot_bridge.hpp"
#include "cobra/bridges/omni_phantom_bridge.hpp"

namespace cobra::bridges {

void registerBridgesPackage(deploy::PackageBuilder& package) {
  package
      .component<ISURRobotBridge>("ISURRobotBridge",
                                  "I-SUR robot through shared memory and a UDP server (thesis §4.5.7)")
      .component<OmniPhantomBridge>("OmniPhantomBridge", "Phantom Omni over TCP (thesis §4.5.9)");
}

}  // namespace cobra::bridges
