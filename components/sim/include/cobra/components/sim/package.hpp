#pragma once
/// @file
/// The "cobra_sim" package: the sim-world components (the simulated robots, patient and devices
/// whose truth the simulated world computes), for packages_list.

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

/// Registers SimulatedISURRobot, SimulatedISURSuturingRobot, SimulatedUR5Robot, PatientSimulator,
/// SimulatedOmniPhantom, CryoConsole, WoundSimulator, and the simulated devices of the drivers:
/// SimulatedPuma260 (the analytic arm), Puma260World (the MuJoCo world), SimulatedFTSens,
/// SimulatedLeapMotion.
void registerSimPackage(deploy::PackageBuilder& package);

}  // namespace cobra::components
