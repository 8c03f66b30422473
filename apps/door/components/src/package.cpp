// The "cobra_door" package: loaded by name (packages_list = { "cobra_door" }) from lib cobra_door.so.
#include <cstdint>

#include "cobra/components/door/door_sim.hpp"
#include "cobra/deploy/package_registry.hpp"

extern "C" std::uint32_t cobra_package_abi() { return cobra::deploy::kPackageAbiVersion; }

extern "C" void cobra_register_package(cobra::deploy::PackageBuilder& package) {
  package.component<cobra::components::DoorSim>(
      "DoorSim", "simulated one-axis arm with a gripper, door handle and door (thesis §2.2, Fig. 2.5)");
}
