#pragma once
/// @file
/// The "cobra_motion" package: motion components (thesis §4.5.2), for packages_list.

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

/// Registers CartesianTrajectoryGenerator, EquivalentWrench and KinematicsSolver (also as
/// KdlKinematicsSolver and ClosedFormKinematicsSolver).
void registerMotionPackage(deploy::PackageBuilder& package);

}  // namespace cobra::components
