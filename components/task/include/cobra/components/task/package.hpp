#pragma once
/// @file
/// The "cobra_task" package: the components of a task's own layer, between its chart and the
/// computation (StateTableFrameGenerator).

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

void registerTaskPackage(deploy::PackageBuilder& package);

}  // namespace cobra::components
