#pragma once
/// @file
/// The "cobra_puncturing" package: the puncturing task's own components (apps/puncturing).

#include "cobra/deploy/package_registry.hpp"

namespace cobra::components {

/// Registers PuncturingFrameGenerator and ScriptedSurgeon.
void registerPuncturingPackage(deploy::PackageBuilder& package);

}  // namespace cobra::components
