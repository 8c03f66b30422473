#pragma once
// The robots' controllers as the planning tests and bench/planning_bench.cpp need them, built
// from cobra::kinematics alone (not from the planner's robot models): one continuity-keeping IK
// per robot (kinematics::ContinuousIk for the UR5 and the puncturing I-SUR,
// kinematics::ContinuousIsurSuturingIk for the two-armed I-SUR), fed the tool poses in each
// robot's base frame and model tool frame, the joints' velocity limits those of the simulated
// robots. Shared by random_queries.hpp (the random walks that make feasible queries) and
// random_queries_test.cpp (the independent re-walk of every solved path).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/kinematics/continuity.hpp"
#include "cobra/kinematics/isur.hpp"
#include "cobra/kinematics/isur_continuity.hpp"
#include "cobra/kinematics/ur5.hpp"
#include "cobra/planning/motion_planner.hpp"
#include "cobra/planning/robot_adapters.hpp"

namespace cobra::planning::test {

/// Period of the controllers' continuity rule here [s]: the simulated robots step at 1 ms; 10 ms
/// steps along the same trajectory bound the same joint velocities (max_velocity · dt) with a
/// tenth of the work.
inline constexpr double kControlPeriod = 0.01;

/// Pose of a Cartesian segment a → b at fraction s as the trajectory generator moves along it:
/// the origin on the straight line, the rotation on the geodesic R_a Rot(u, s θ).
inline KDL::Frame cartesianPoint(const KDL::Frame& a, const KDL::Frame& b, double s) {
  KDL::Vector axis;
  const double angle = (a.M.Inverse() * b.M).GetRotAngle(axis);
  return KDL::Frame(angle > 0.0 ? a.M * KDL::Rotation::Rot2(axis, s * angle) : a.M, a.p + (b.p - a.p) * s);
}

/// How long the Cartesian trajectory generator takes over segment a → b [s]: each position axis
/// at most `linear` m/s, the rotation at most `angular` rad/s, never less than `blend` s.
inline double generatorDuration(double linear, double angular, double blend, const DualPose& a, const DualPose& b) {
  double duration = blend;
  for (const auto& [from, to] : {std::pair{&a.first, &b.first}, std::pair{&a.second, &b.second}}) {
    for (int i = 0; i < 3; ++i) duration = std::max(duration, std::abs(to->p(i) - from->p(i)) / linear);
    KDL::Vector axis;
    duration = std::max(duration, (from->M.Inverse() * to->M).GetRotAngle(axis) / angular);
  }
  return duration;
}

/// The controllers of a scene's robots: one continuity-keeping IK per robot, fed the tool poses
/// of q in its base frame and model tool frame. Not thread-safe (the solvers warm-start).
class Controllers {
 public:
  explicit Controllers(StateValidator& validator) : validator_(validator) {
    for (const RobotPlacement& robot : validator.scene().robots) {
      if (robot.name == "ur5") {
        auto solver = std::make_unique<kinematics::Ur5Solver>(kinematics::Ur5Parameters{}, kinematics::Ur5Solver::defaultLimits(),
                                                              KDL::Frame::Identity(), Ur5Model::defaultProbe());
        single_.push_back(std::make_unique<kinematics::ContinuousIk>(
            *solver, std::vector<double>(6, Ur5Model::kMaxJointVelocity), kControlPeriod));
        solvers_.push_back(std::move(solver));
      } else if (robot.tool_indices.size() == 1) {
        auto solver = std::make_unique<kinematics::IsurPuncturingSolver>();
        std::vector<double> velocity(8, IsurPuncturingModel::kMaxRevoluteVelocity);
        std::fill_n(velocity.begin(), 3, IsurPuncturingModel::kMaxSliderVelocity);
        single_.push_back(std::make_unique<kinematics::ContinuousIk>(*solver, velocity, kControlPeriod));
        solvers_.push_back(std::move(solver));
      } else {
        suturing_ = std::make_unique<kinematics::IsurSuturingSolver>();
        std::vector<double> velocity(14, IsurPuncturingModel::kMaxRevoluteVelocity);
        std::fill_n(velocity.begin(), 3, IsurPuncturingModel::kMaxSliderVelocity);
        two_tools_ = std::make_unique<kinematics::ContinuousIsurSuturingIk>(*suturing_, velocity, kControlPeriod);
        single_.push_back(nullptr);
      }
    }
  }

  /// One control step (kControlPeriod) to the tool poses `tools` from joints `q` (updated): false
  /// with `why` when a robot's continuity-keeping IK refuses it (q then unchanged for that robot
  /// and those after it).
  bool step(const DualPose& tools, std::vector<double>& q, std::string& why) {
    const SceneDescription& scene = validator_.scene();
    for (std::size_t r = 0; r < scene.robots.size(); ++r) {
      const RobotPlacement& robot = scene.robots[r];
      const std::size_t offset = validator_.jointOffset(r), n = validator_.model(r).jointCount();
      KDL::Frame targets[2];
      for (std::size_t t = 0; t < robot.tool_indices.size(); ++t)
        targets[t] = robot.base_in_world.Inverse() * (robot.tool_indices[t] == 0 ? tools.first : tools.second) *
                     robot.toolFrame(t).Inverse();
      KDL::JntArray current(static_cast<unsigned>(n)), next(static_cast<unsigned>(n));
      for (std::size_t j = 0; j < n; ++j) current(static_cast<unsigned>(j)) = q[offset + j];
      const kinematics::IkStatus status = single_[r] ? single_[r]->solve(targets[0], current, next)
                                                     : two_tools_->solve(targets[0], targets[1], current, next);
      if (status != kinematics::IkStatus::Ok) {
        why = "robot '" + robot.name + "': " + std::string(kinematics::toString(status));
        return false;
      }
      for (std::size_t j = 0; j < n; ++j) q[offset + j] = next(static_cast<unsigned>(j));
    }
    return true;
  }

 private:
  StateValidator& validator_;
  std::vector<std::unique_ptr<kinematics::KinematicsSolver>> solvers_;
  std::vector<std::unique_ptr<kinematics::ContinuousIk>> single_;
  std::unique_ptr<kinematics::IsurSuturingSolver> suturing_;
  std::unique_ptr<kinematics::ContinuousIsurSuturingIk> two_tools_;
};

}  // namespace cobra::planning::test
