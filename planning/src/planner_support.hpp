#pragma once
// Internal helpers shared by the SE(3)×SE(3) search (motion_planner.cpp) and the joint-space
// search (joint_path.cpp).

#include <ompl/base/Planner.h>
#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/util/Console.h>

#include <chrono>
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

/// `result` with its status, message and the time since `started`.
inline PlanResult finished(PlanResult result, PlanStatus status, std::string message,
                           std::chrono::steady_clock::time_point started) {
  result.status = status;
  result.message = std::move(message);
  result.planning_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace cobra::planning::detail
