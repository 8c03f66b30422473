#pragma once
/// @file
/// The StepVerifier of a procedure walk (procedure_walk.hpp) made of the planning library's
/// MotionPlanner: each planned step is asked of the planner of the arm whose chart runs it, as
/// that chart's MotionPlanner component asks it (the goal alternatives in their order, each with
/// its goal and room checks before the search, the search from the joints where the previous step
/// left the robots, the then_* follow-on after it, the next seed after a failed search), and each
/// motion primitive is walked straight with the control path's IK (MotionPlanner::checkFollowOn).
/// Library code: planning and task, no runtime.

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "cobra/planning/motion_planner.hpp"
#include "cobra/task/procedure_walk.hpp"

namespace cobra::task {

/// A planned step's path as the walk found it: from the joints `start` to the goal it took.
struct CheckedPath {
  ProcedureStep step;
  planning::JointState start;
  planning::DualPose goal;
  std::size_t alternative = 0;  ///< the goal alternative taken (0-based, the table's order)
  planning::PlanResult result;  ///< solved: waypoints and joint_waypoints from start to goal
};

class PlannerStepVerifier final : public StepVerifier {
 public:
  /// `planners[a]`: the planner arm a's chart plans with (the run's options and seed), both over
  /// one scene; borrowed, they must outlive this. `start`: the robots' joints before the first
  /// step (StateValidator::jointOffset order; m, rad).
  PlannerStepVerifier(std::array<planning::MotionPlanner*, 2> planners, planning::StateValidator& validator,
                      planning::JointState start);

  StepOutcome planned(const ProcedureStep& step, std::span<const GoalCandidate> candidates) override;
  StepOutcome straight(const ProcedureStep& step, const PosePair& from, const PosePair& to) override;

  /// The robots' joints after the last step that passed.
  const planning::JointState& joints() const { return joints_; }
  /// The validity checks the searches of the walk took (the planners' unit of work).
  std::size_t validityChecks() const { return checks_; }
  /// The path of every planned step that passed, in the walk's order: what the run can follow
  /// instead of searching again from nearly the same joints (a search from other joints may take
  /// another way, which was not verified).
  const std::vector<CheckedPath>& paths() const { return paths_; }

 private:
  std::array<planning::MotionPlanner*, 2> planners_;
  planning::StateValidator& validator_;
  planning::JointState joints_;
  std::size_t checks_ = 0;
  std::vector<CheckedPath> paths_;
};

}  // namespace cobra::task
