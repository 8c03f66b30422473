#pragma once
/// @file
/// The component packages built into cobra, registered in one place for the `cobra` tool, the
/// applications and the tests: what a deployment file's packages_list can name without a shared
/// library.

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

/// Makes the framework's own component packages loadable by `packages`: cobra_signal,
/// cobra_motion, cobra_task, cobra_coordination, cobra_control, cobra_planning, cobra_bridges,
/// cobra_drivers, cobra_sim, cobra_monitoring and cobra_reporting. An application's package
/// (apps/*/components) is never built in: it is a shared library found by name on the search path.
/// @throws core::Error when one of these names is already known to `packages`.
void addBuiltinPackages(deploy::PackageRegistry& packages);

}  // namespace cobra::components
