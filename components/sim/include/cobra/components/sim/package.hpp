#pragma once
/// @file
/// The "cobra_sim" package: the simulated bridges of the puncturing set-up and the decision
/// components that turn its sensor data into events, for packages_list.

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

/// Registers SimulatedISURRobot, SimulatedUR5Robot, PatientSimulator, SimulatedOmniPhantom,
/// NeedleInsertionMonitor and UltrasoundMonitor.
void registerSimPackage(deploy::PackageBuilder& package);

}  // namespace cobra::components
