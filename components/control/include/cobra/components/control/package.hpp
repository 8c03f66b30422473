#pragma once
/// @file
/// The "cobra_control" package: VariableAdmittance, TransparencyLayer, PassivityLayer.

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

void registerControlPackage(deploy::PackageBuilder& package);

}  // namespace cobra::components
