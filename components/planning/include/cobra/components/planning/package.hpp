#pragma once
/// @file
/// The "cobra_planning" package: the Motion Planner (thesis §4.5.1) and the State Validator
/// (§5.4.2), for packages_list.

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

/// Registers MotionPlanner and StateValidator.
void registerPlanningPackage(deploy::PackageBuilder& package);

}  // namespace cobra::components
