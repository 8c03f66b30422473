#pragma once
/// @file
/// The "cobra_coordination" package: the Supervisor component, for packages_list.

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

/// Registers Supervisor.
void registerCoordinationPackage(deploy::PackageBuilder& package);

}  // namespace cobra::components
