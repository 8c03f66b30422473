#pragma once
/// @file
/// The component packages built into cobra, registered in one place for the `cobra` tool, the
/// applications and the tests: what a deployment file's packages_list can name without a shared
/// library.

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

/// Makes cobra_signal, cobra_motion, cobra_coordination, cobra_control, cobra_planning,
/// cobra_bridges, cobra_drivers, cobra_sim, cobra_monitoring and the puncturing task's
/// cobra_puncturing (apps/puncturing/components) loadable by `packages`.
/// @throws core::Error when one of these names is already known to `packages`.
void addBuiltinPackages(deploy::PackageRegistry& packages);

}  // namespace cobra::components
