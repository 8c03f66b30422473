#pragma once
/// @file
/// The "cobra_signal" package: SineGenerator, Gain, ThresholdDetector, Recorder, Constant.

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

void registerSignalPackage(deploy::PackageBuilder& package);

}  // namespace cobra::components
