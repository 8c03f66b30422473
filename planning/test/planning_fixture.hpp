#pragma once
// Shared by the planning tests: the test data folder and the two-robot test scene with its
// stand-in robots.

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "cobra/planning/state_validator.hpp"
#include "stand_in_robots.hpp"

namespace cobra::planning::test {

inline std::filesystem::path dataDir() { return std::filesystem::path(COBRA_SOURCE_DIR) / "planning/test/data"; }

inline std::string readText(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

/// two_robots.scene plus `extra` statements: gantry "isur" reaching |x|,|y| <= 0.5 m and
/// z in [0.15, 0.8] m, free flyer "ur5" reaching 0.7 m around (0, 0, 0.3) m.
inline SceneDescription twoRobotScene(const std::string& extra = "") {
  return parseScene(readText(dataDir() / "two_robots.scene") + extra, "two_robots.scene", dataDir());
}

inline RobotModels twoRobotModels() {
  return {{"isur", std::make_shared<StandInGantry>(0.5, 0.15, 0.8, 0.1)},
          {"ur5", std::make_shared<StandInFreeFlyer>(KDL::Vector(0, 0, 0.3), 0.7)}};
}

/// Tools pointing down (needle along world -z is the tool's +z rotated by pi about x).
inline DualPose toolsAt(const KDL::Vector& first, const KDL::Vector& second) {
  return {KDL::Frame(KDL::Rotation::Identity(), first), KDL::Frame(KDL::Rotation::Identity(), second)};
}

}  // namespace cobra::planning::test
