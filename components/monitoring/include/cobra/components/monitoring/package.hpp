#pragma once
/// @file
/// The "cobra_monitoring" package: the Decision components of the puncturing task's situation
/// awareness, for packages_list.

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

/// Registers NeedleInsertionMonitor and UltrasoundMonitor.
void registerMonitoringPackage(deploy::PackageBuilder& package);

}  // namespace cobra::components
