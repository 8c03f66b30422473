#pragma once
/// @file
/// The "cobra_drivers" package: Puma260EtherCATMaster, FTSensDriver, LeapMotionDriver, and the
/// backend scheme `socketcan` of fieldbus::CanBus (fieldbus::SocketCanBus).

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

void registerDriversPackage(deploy::PackageBuilder& package);

}  // namespace cobra::components
