#pragma once
/// @file
/// The "cobra_bridges" package: network robot bridges (thesis §4.5.7, §4.5.9), for packages_list.

#include "cobra/deploy/package_registry.hpp"

namespace cobra::bridges {

/// Registers ISURRobotBridge and OmniPhantomBridge.
void registerBridgesPackage(deploy::PackageBuilder& package);

}  // namespace cobra::bridges
