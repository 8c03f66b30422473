#pragma once
// The puncturing scene of the planning tests with its real robot models, for the tests of the
// planned walk and of the run following it (planned_walk_test, verified_paths_test): small
// queries of a second or less.

#include <filesystem>
#include <numbers>

#include "cobra/planning/motion_planner.hpp"
#include "cobra/planning/robot_adapters.hpp"

namespace cobra::task::test {

/// The joints apps/puncturing/deployment/world.lua starts the robots at: the needle 10° from
/// vertical at (-0.05, 0.05, 0.26) m, the probe pointing down at (0.2, -0.25, 0.3) m.
inline const planning::JointState kStart{0.00202, 0.00249, 0.204398, 0,       0,      0.85,   0.55,
                                         0,       0.798,   -1.4495,  -1.714, 1.5925, -1.571, -2.344};

/// planning/test/scenes/puncturing.scene with the application's needle frame (z along the needle).
inline planning::StateValidator walkValidator() {
  planning::SceneDescription scene =
      planning::loadScene(std::filesystem::path(COBRA_SOURCE_DIR) / "planning/test/scenes/puncturing.scene");
  for (planning::RobotPlacement& robot : scene.robots)
    if (robot.name == "isur") robot.setToolFrame(0, KDL::Frame(KDL::Rotation::RPY(0.0, std::numbers::pi / 2, 0.0)));
  planning::RobotModels models = planning::makeRobotModels(scene);
  return planning::StateValidator(std::move(scene), std::move(models));
}

/// The run's options on that scene (the MotionPlanner component's tool bounds, m), a work budget
/// instead of a time limit (deterministic) and the trajectory generators' speeds (m/s, rad/s).
inline planning::PlannerOptions walkOptions() {
  planning::PlannerOptions o;
  o.first_bounds = {{-0.3, -0.3, 0.0}, {0.3, 0.3, 0.5}}, o.second_bounds = {{-0.4, -0.5, 0.0}, {0.4, 0.4, 0.6}};
  o.max_validity_checks = 200000;
  o.max_linear_velocity = 0.04, o.max_angular_velocity = 0.15;
  o.tool_names = {"needle", "probe"};
  return o;
}

/// The probe pointing down at `p` (m).
inline KDL::Frame probeAt(const KDL::Vector& p) { return KDL::Frame(KDL::Rotation::RotX(std::numbers::pi), p); }

}  // namespace cobra::task::test
