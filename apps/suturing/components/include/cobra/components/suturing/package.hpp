#pragma once
/// @file
/// The "cobra_suturing" package: the suturing task's own components (apps/suturing).

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

/// Registers StitchPlanner.
void registerSuturingPackage(deploy::PackageBuilder& package);

}  // namespace cobra::components
