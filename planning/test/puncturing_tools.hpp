#pragma once
// The puncturing scene of the planning tests (planning/test/scenes) and its tools pointing down,
// shared by the planning tests and the planning components' tests (components/planning/test).

#include <filesystem>
#include <numbers>

#include <kdl/frames.hpp>

namespace cobra::planning::test {

/// The folder of puncturing.scene and its meshes.
inline std::filesystem::path scenes() { return std::filesystem::path(COBRA_SOURCE_DIR) / "planning/test/scenes"; }

/// Needle tip at (x, y, z) [m] pointing straight down (its tip frame's x axis = world -z).
inline KDL::Frame needleDown(double x, double y, double z) {
  return {KDL::Rotation::RotY(std::numbers::pi / 2), KDL::Vector(x, y, z)};
}

/// Probe tip at (x, y, z) [m] pointing straight down (its tip frame's z axis = world -z).
inline KDL::Frame probeDown(double x, double y, double z) {
  return {KDL::Rotation::RotX(std::numbers::pi), KDL::Vector(x, y, z)};
}

}  // namespace cobra::planning::test
