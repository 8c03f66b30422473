#include "cobra/task/planned_walk.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cobra::task {
namespace {

constexpr double kTrackStep = 1e-4;   // m
constexpr double kTrackAngle = 1e-4;  // rad

planning::DualPose dual(const PosePair& pair) { return {pair[0], pair[1]}; }

/// The pose at fraction s of a straight motion as the trajectory generator makes it: the origin on
/// the line, the rotation on the geodesic.
KDL::Frame along(const KDL::Frame& a, const KDL::Frame& b, double s) {
  KDL::Vector axis;
  const double angle = (a.M.Inverse() * b.M).GetRotAngle(axis);
  return KDL::Frame(angle > 0.0 ? a.M * KDL::Rotation::Rot2(axis, s * angle) : a.M, a.p + (b.p - a.p) * s);
}

std::string reason(const planning::PlanResult& result) {
  return std::string(planning::toString(result.status)) + ": " + result.message;
}

}  // namespace

PlannerStepVerifier::PlannerStepVerifier(std::array<planning::MotionPlanner*, 2> planners,
                                         planning::StateValidator& validator, planning::JointState start)
    : planners_(planners), validator_(validator), joints_(std::move(start)) {
  if (planners_[0] == nullptr || planners_[1] == nullptr)
    throw std::invalid_argument("PlannerStepVerifier: a planner per arm is needed");
  if (joints_.size() != validator_.jointCount())
    throw std::invalid_argument("PlannerStepVerifier: the start has " + std::to_string(joints_.size()) +
                                " joints; the scene's robots have " + std::to_string(validator_.jointCount()));
}

StepOutcome PlannerStepVerifier::planned(const ProcedureStep& step, std::span<const GoalCandidate> candidates) {
  planning::MotionPlanner& planner = *planners_[step.arm];
  StepOutcome outcome;
  std::string refused;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const GoalCandidate& c = candidates[k];
    const planning::DualPose goal = dual(c.goal);
    planning::PlanResult result;
    result.status = planning::PlanStatus::Solved;
    // As the MotionPlanner component: the goal and room checks first when there is a choice or a
    // room to leave, then the search, which checks the motion primitive that follows from where
    // its path ends (MotionPlanner::planPath with `then`).
    const std::optional<planning::DualPose> then =
        c.has_then ? std::optional<planning::DualPose>(dual(c.then)) : std::nullopt;
    if (candidates.size() > 1 || !c.rooms.empty()) {
      result = planner.checkGoal(joints_, goal, then);
      for (std::size_t r = 0; r < c.rooms.size() && result.solved(); ++r)
        result = planner.checkMotion(joints_, dual(c.rooms[r].first), dual(c.rooms[r].second));
    }
    if (result.solved()) {
      result = planner.planPath(joints_, goal, then);
      checks_ += result.validity_checks;
      if (!result.solved()) {
        // The component explores with the next seed after a failed search: so does the walk.
        const std::uint32_t seed = planner.options().seed;
        planner.setSeed(seed == UINT32_MAX ? 1 : seed + 1);
      }
    }
    if (result.solved()) {
      outcome.ok = true;
      outcome.chosen = k;
      outcome.reached = c.goal;
      paths_.push_back({step, joints_, goal, k, result});
      joints_ = result.joint_waypoints.back();
      return outcome;
    }
    if (candidates.size() == 1) {
      outcome.why = reason(result);
      return outcome;
    }
    refused += std::string(refused.empty() ? "" : "; ") + c.datum + ": " + reason(result);
  }
  outcome.why = "none of the " + std::to_string(candidates.size()) + " goal alternatives can be taken: " + refused;
  return outcome;
}

StepOutcome PlannerStepVerifier::straight(const ProcedureStep& step, const PosePair& from, const PosePair& to) {
  planning::MotionPlanner& planner = *planners_[step.arm];
  StepOutcome outcome;
  const planning::PlanResult result = planner.checkFollowOn(joints_, dual(from), dual(to));
  if (!result.solved()) {
    outcome.why = reason(result);
    return outcome;
  }
  // Where the joints end: the continuity-keeping IK followed along the motion, as the robots
  // follow it (one jump to the end could resolve a redundant robot's redundancy otherwise).
  // Steps of at most kTrackStep m and kTrackAngle rad per tool: near the I-SUR's wrist lock
  // (a vertical needle) coarser steps resolve its redundancy unlike the robot, which tracks its
  // command every 1 ms (tens of micrometres): a 0.3 rad tilt ended 0.1 rad elsewhere in its
  // wrist with 1 mrad steps than with finer ones (test/planned_walk_test.cpp).
  double span = 0.0;
  for (std::size_t a = 0; a < 2; ++a) {
    KDL::Vector axis;
    span = std::max({span, (to[a].p - from[a].p).Norm() / kTrackStep,
                     (from[a].M.Inverse() * to[a].M).GetRotAngle(axis) / kTrackAngle});
  }
  const auto steps = std::max<std::size_t>(planner.options().verify_points_per_segment,
                                           static_cast<std::size_t>(std::ceil(span)));
  planning::JointState q = joints_, next(joints_.size());
  for (std::size_t k = 1; k <= steps; ++k) {
    const double s = static_cast<double>(k) / static_cast<double>(steps);
    std::size_t robot = 0;
    if (validator_.inverseNear({along(from[0], to[0], s), along(from[1], to[1], s)}, q, next, robot) !=
        planning::Reachability::Reachable) {
      outcome.why = "robot '" + validator_.scene().robots[robot].name + "' loses its IK along the motion";
      return outcome;
    }
    q.swap(next);
  }
  joints_ = std::move(q);
  outcome.ok = true;
  outcome.reached = to;
  return outcome;
}

}  // namespace cobra::task
