#include "cobra/bridges/package.hpp"

#include "cobra/bridges/igtl_bridge.hpp"
#include "cobra/bridges/isur_robot_bridge.hpp"
#include "cobra/bridges/omni_phantom_bridge.hpp"

namespace cobra::bridges {

void registerBridgesPackage(deploy::PackageBuilder& package) {
  types::registerPointList();  // the IgtlBridge's plan (Geometry.PointList): Lua, CSV
  package
      .component<ISURRobotBridge>("ISURRobotBridge",
                                  "I-SUR robot through shared memory and a UDP server (thesis §4.5.7)")
      .component<OmniPhantomBridge>("OmniPhantomBridge", "Phantom Omni over TCP (thesis §4.5.9)")
      .component<IgtlBridge>("IgtlBridge", "OpenIGTLink to a navigation program (3D Slicer, PLUS; thesis §4.2)");
}

}  // namespace cobra::bridges
