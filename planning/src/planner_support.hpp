#pragma once
// Internal helpers shared by the SE(3)×SE(3) search (motion_planner.cpp), the joint-space
// search (joint_path.cpp) and its straight motions (straight_motions.cpp).

#include <ompl/base/Planner.h>
#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/util/Console.h>

#include <chrono>
#include <cstdio>
#include <optional>
#include <string>

#include "cobra/planning/motion_planner.hpp"

namespace cobra::planning::detail {

/// Lowers OMPL's console output for one scope (OMPL logs through a process-wide level).
class OmplLogLevel {
 public:
  explicit OmplLogLevel(ompl::msg::LogLevel level) : previous_(ompl::msg::getLogLevel()) {
    ompl::msg::setLogLevel(level);
  }
  ~OmplLogLevel() { ompl::msg::setLogLevel(previous_); }
  OmplLogLevel(const OmplLogLevel&) = delete;
  OmplLogLevel& operator=(const OmplLogLevel&) = delete;

 private:
  ompl::msg::LogLevel previous_;
};

/// The planner `options.planner` names (one of plannerNames()) on `si`.
ompl::base::PlannerPtr makePlanner(const PlannerOptions& options, const ompl::base::SpaceInformationPtr& si);

/// Runs the planner `options.planner` names on `setup` (its space, validity checker, start and
/// goal set) until `stop`; the path found, simplified when `options.simplify` (step-bounded, not
/// time-bounded, so the result stays reproducible), or nullopt when no exact solution was found.
std::optional<ompl::geometric::PathGeometric> solve(ompl::geometric::SimpleSetup& setup, const PlannerOptions& options,
                                                   const ompl::base::PlannerTerminationCondition& stop);

/// "(x, y, z) m" of a frame's origin, for messages.
inline std::string position(const KDL::Frame& f) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.4f, %.4f, %.4f) m", f.p.x(), f.p.y(), f.p.z());
  return text;
}

/// Pose of a Cartesian segment at fraction s as the trajectory generator moves along it: the
/// origin on the straight line, the rotation on the geodesic R_a Rot(u, s θ).
inline KDL::Frame interpolate(const KDL::Frame& a, const KDL::Frame& b, double s) {
  KDL::Vector axis;
  const double angle = (a.M.Inverse() * b.M).GetRotAngle(axis);
  return KDL::Frame(angle > 0.0 ? a.M * KDL::Rotation::Rot2(axis, s * angle) : a.M, a.p + (b.p - a.p) * s);
}

/// `result` with its status, message and the time since `started`.
inline PlanResult finished(PlanResult result, PlanStatus status, std::string message,
                           std::chrono::steady_clock::time_point started) {
  result.status = status;
  result.message = std::move(message);
  result.planning_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace cobra::planning::detail
