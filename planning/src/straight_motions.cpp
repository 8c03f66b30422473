// MotionPlanner's straight motions (motion_planner.hpp): the motion primitives checked after a
// planned goal (checkFollowOn) or apart from a path (checkMotion), and the dense walk of a
// Cartesian segment with the control path's continuity-keeping IK that they and the path's
// verification share, within the joints' velocity limits at the generator's speeds.

#include "cobra/planning/motion_planner.hpp"

#include "planner_support.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace cobra::planning {

using detail::interpolate;
using detail::position;

double MotionPlanner::segmentDuration(const DualPose& a, const DualPose& b) const {
  double duration = options_.blend_time;
  for (const auto& [from, to] : {std::pair{&a.first, &b.first}, std::pair{&a.second, &b.second}}) {
    for (int axis = 0; axis < 3; ++axis)
      duration = std::max(duration, std::abs(to->p(axis) - from->p(axis)) / options_.max_linear_velocity);
    KDL::Vector unused;
    duration = std::max(duration, (from->M.Inverse() * to->M).GetRotAngle(unused) / options_.max_angular_velocity);
  }
  return duration;
}

void MotionPlanner::setVelocityLimits() {
  max_velocity_.assign(validator_.jointCount(), 0.0);
  for (std::size_t r = 0; r < validator_.scene().robots.size(); ++r) {
    RobotModel& model = validator_.model(r);
    std::vector<double> lower(model.jointCount()), upper(model.jointCount());
    model.jointLimits(lower, upper, std::span<double>(max_velocity_).subspan(validator_.jointOffset(r), model.jointCount()));
  }
}

PlanResult MotionPlanner::checkMotion(const JointState& near, const DualPose& from, const DualPose& to) {
  PlanResult result;
  if (!validator_.hasJointSpace() || near.size() != validator_.jointCount() || !isFinitePose(from) ||
      !isFinitePose(to)) {
    result.status = PlanStatus::InvalidInput;
    result.message = "a motion to verify: joints or poses are not a state of this scene";
    return result;
  }
  const std::string what = "the straight motion from " + position(from.first) + " and " + position(from.second) +
                           " to " + position(to.first) + " and " + position(to.second);
  // Its start joints as planPath takes a goal with a motion after it: the goal IK's first goal,
  // or its alternative when the first's state is not valid or the motion cannot be made from it.
  JointState q;
  bool alternative_taken = false;
  result = goalJoints(near, from, q, alternative_taken);
  if (!result.solved()) {
    result.message = what + " cannot start: " + result.message;
    return result;
  }
  setVelocityLimits();
  const auto refusal = [&](JointState& start, ValidityResult& rejected) {
    rejected = checkState(start, true);
    if (!rejected.valid()) return what + " cannot start: " + describe(rejected);
    std::string failure;
    return walk(from, to, start, failure, true) ? std::string() : what + " cannot be made: " + failure;
  };
  JointState walked = q;
  std::string refused = refusal(walked, result.rejected);
  if (!refused.empty() && !alternative_taken) {
    JointState alternative(q.size());
    std::size_t robot = 0;
    ValidityResult rejected;
    if (validator_.inverseGoalAlternative(from, near, alternative, robot) == Reachability::Reachable &&
        refusal(alternative, rejected).empty())
      refused.clear();
  }
  if (!refused.empty()) {
    result.status = PlanStatus::InvalidGoal;
    result.message = refused;
  }
  return result;
}

PlanResult MotionPlanner::checkFollowOn(const JointState& joints, const DualPose& from, const DualPose& to) {
  PlanResult result;
  result.status = PlanStatus::Solved;
  if (joints.size() != validator_.jointCount() || !isFinitePose(from) || !isFinitePose(to)) {
    result.status = PlanStatus::InvalidInput;
    result.message = "the motion after the goal: joints or poses are not a state of this scene";
    return result;
  }
  JointState q = joints;
  std::string failure;
  if (max_velocity_.size() != q.size()) setVelocityLimits();  // the path needed no search
  if (!walk(from, to, q, failure, true)) {
    result.status = PlanStatus::InvalidGoal;
    result.message = "the straight motion after the goal, to " + position(to.first) + " and " + position(to.second) +
                     ", cannot be made: " + failure;
  }
  return result;
}

bool MotionPlanner::walk(const DualPose& a, const DualPose& b, JointState& q, std::string& failure,
                         bool primitive_contacts_apart) {
  // The generator takes at least `duration` s over the segment, uniformly in s on its linear part:
  // each joint's change over a step of the walk must fit its velocity limit (with the margin) over
  // the step's share of that time. The density follows the joint speeds: every step is solved at
  // its midpoint too, and a step in which a joint's speed changes by more than kSpeedChange of its
  // allowed speed between the two halves (a peak the step would average away: near a singular
  // set, e.g. the UR5's shoulder where the wrist point passes near the base axis, a joint turns
  // fast over a few milliseconds) or exceeds it is walked again in halves, down to steps of
  // kFinestStep s, the controllers' period; it grows back to 1/verify_points_per_segment after.
  constexpr double kSpeedChange = 0.5;  // [1] of the allowed speed
  constexpr double kFinestStep = 1e-3;  // s: the robots' control period (1 kHz)
  const double coarsest = 1.0 / static_cast<double>(options_.verify_points_per_segment);
  const double duration = segmentDuration(a, b);
  JointState middle(q.size()), next(q.size());
  const auto solve = [&](double s, const JointState& from, JointState& to) {
    const DualPose pose{interpolate(a.first, b.first, s), interpolate(a.second, b.second, s)};
    std::size_t robot = 0;
    const Reachability reached = validator_.inverseNear(pose, from, to, robot);
    if (reached == Reachability::Reachable) return true;
    failure = "robot '" + validator_.scene().robots[robot].name + "' " +
              (reached == Reachability::OtherBranch ? "would change its IK branch" : "has no IK solution") + " at " +
              std::to_string(s) + " of a segment";
    return false;
  };
  double s = 0.0, h = coarsest;
  while (s < 1.0) {
    const double s1 = 1.0 - s <= h * (1.0 + 1e-9) ? 1.0 : s + h;
    const double half = 0.5 * (s1 - s);
    if (!solve(s + half, q, middle) || !solve(s1, middle, next)) return false;
    const bool finest = (s1 - s) * duration <= kFinestStep;
    std::size_t worst = 0;
    double worst_ratio = 0.0, worst_change = 0.0;
    for (std::size_t j = 0; j < q.size(); ++j) {
      const double allowed = options_.joint_velocity_margin * max_velocity_[j] * duration * half;
      const double first = middle[j] - q[j], second = next[j] - middle[j];
      const double ratio = std::max(std::abs(first), std::abs(second)) / allowed;
      if (ratio > worst_ratio) {
        worst_ratio = ratio;
        worst = j;
      }
      worst_change = std::max(worst_change, std::abs(second - first) / allowed);
    }
    if (!finest && (worst_ratio > 1.0 || worst_change > kSpeedChange)) {
      h = half;  // walk this step again in halves
      continue;
    }
    if (worst_ratio > 1.0) {
      const double allowed = options_.joint_velocity_margin * max_velocity_[worst] * duration * half;
      const double step = std::abs(middle[worst] - q[worst]) > std::abs(next[worst] - middle[worst])
                              ? middle[worst] - q[worst]
                              : next[worst] - middle[worst];
      failure = "joint " + std::to_string(worst) + " steps " + std::to_string(step) + " where " +
                std::to_string(allowed) + " is allowed at " + std::to_string(s1) +
                " of a segment (IK discontinuity)";
      return false;
    }
    q.swap(next);
    s = s1;
    if (worst_change < 0.5 * kSpeedChange && worst_ratio < 0.5) h = std::min(coarsest, 2.0 * h);
    const ValidityResult validity = checkState(q, primitive_contacts_apart);
    if (!validity.valid()) {
      failure = describe(validity) + " at " + std::to_string(s) + " of a segment";
      return false;
    }
  }
  return true;
}

}  // namespace cobra::planning
