#include "cobra/task/verified_paths.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace cobra::task {
namespace {

KDL::Frame& tool(planning::DualPose& pair, std::size_t arm) { return arm == 0 ? pair.first : pair.second; }
const KDL::Frame& tool(const planning::DualPose& pair, std::size_t arm) { return arm == 0 ? pair.first : pair.second; }

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

planning::PlanResult refusal(const std::string& message) {
  planning::PlanResult result;
  result.status = planning::PlanStatus::NoSolution;
  result.message = message;
  return result;
}

}  // namespace

VerifiedPaths::VerifiedPaths(planning::StateValidator& validator, const planning::PlannerOptions& options,
                             std::size_t robot, std::size_t arm, FollowTolerances tolerances)
    : validator_(validator), checker_(validator, options), robot_(robot), arm_(arm), tolerances_(tolerances) {
  if (robot_ >= validator_.scene().robots.size() || arm_ > 1)
    throw std::invalid_argument("VerifiedPaths: robot " + std::to_string(robot_) + " or arm " + std::to_string(arm_) +
                                " is not one of the scene's");
}

void VerifiedPaths::assign(std::vector<CheckedPath> paths, std::vector<std::string> names, bool ends_walk) {
  paths_ = std::move(paths);
  std::reverse(paths_.begin(), paths_.end());  // the next at the back
  names_ = std::move(names);
  names_.resize(paths_.size());
  std::reverse(names_.begin(), names_.end());
  assigned_ = paths_.size();
  ends_walk_ = ends_walk;
  left_.clear();
}

double VerifiedPaths::apart(const planning::JointState& a, const planning::JointState& b) const {
  const std::size_t from = validator_.jointOffset(robot_), to = from + validator_.model(robot_).jointCount();
  double off = 0.0;
  for (std::size_t j = from; j < to && j < a.size() && j < b.size(); ++j) off = std::max(off, std::abs(a[j] - b[j]));
  return off;
}

bool VerifiedPaths::leave(const std::string& why, planning::PlanResult& result) {
  left_ = "left the verified procedure at planned step " + std::to_string(assigned_ - paths_.size() + 1) + " of " +
          std::to_string(assigned_) + " (" + names_.back() + "): " + why + "; verify the procedure again";
  paths_.clear();
  names_.clear();
  result = refusal(left_);
  return true;
}

std::string VerifiedPaths::recheck(const planning::JointState& start, const planning::DualPose& start_poses,
                                   const planning::DualPose& goal, planning::PlanResult& path) {
  // This robot's verified waypoints from where it is to the goal asked, the other robot held
  // where it really is (e.g. the UR5's probe where the skin pushed it, a few mm from where the
  // walk put it).
  const std::size_t from = validator_.jointOffset(robot_), to = from + validator_.model(robot_).jointCount();
  const std::size_t other = 1 - arm_;
  path = paths_.back().result;
  path.waypoints.front() = start_poses;
  tool(path.waypoints.back(), arm_) = tool(goal, arm_);
  for (std::size_t k = 0; k < path.waypoints.size(); ++k) {
    tool(path.waypoints[k], other) = tool(start_poses, other);
    planning::JointState& q = path.joint_waypoints[k];
    for (std::size_t j = 0; j < q.size(); ++j)
      if (j < from || j >= to || k == 0) q[j] = start[j];
    const planning::ValidityResult valid = validator_.checkJoints(q);
    if (!valid.valid())
      return "waypoint " + std::to_string(k) + " of its verified path is not valid with the other robot where it is: " +
             planning::describe(valid);
  }
  // Each edge walked densely (the first from where this robot really is, which may differ from
  // where the walk put it: the way onto the path).
  for (std::size_t k = 1; k < path.waypoints.size(); ++k) {
    const planning::PlanResult edge =
        checker_.checkFollowOn(path.joint_waypoints[k - 1], path.waypoints[k - 1], path.waypoints[k]);
    if (!edge.solved())
      return "segment " + std::to_string(k) + " of its verified path cannot be followed from where the robots are: " +
             edge.message;
  }
  return {};
}

bool VerifiedPaths::follow(const planning::JointState& start, const planning::DualPose& start_poses,
                           const planning::DualPose& goal, std::size_t alternative, planning::PlanResult& result) {
  if (!left_.empty()) {  // left before: no search until verified again
    result = refusal(left_);
    return true;
  }
  if (paths_.empty()) return false;
  const CheckedPath& next = paths_.back();
  if (next.start.size() != start.size()) return leave("the scene's joints changed", result);
  const double off = apart(start, next.start);
  if (off > tolerances_.start)
    return leave("the robot is " + number(off) + " (m or rad) from the joints where the verification started this "
                 "step (at most " + number(tolerances_.start) + ")", result);
  if (alternative != next.alternative) {
    // Another goal alternative than the walk took from here: the run takes the walk's, whose way
    // was verified (a search may find a way to this one that was not).
    result = refusal("not the goal alternative the procedure's verification took from here (it took alternative " +
                     std::to_string(next.alternative + 1) + ")");
    return true;
  }
  const KDL::Frame& asked = tool(goal, arm_);
  const KDL::Frame& verified = tool(next.goal, arm_);
  KDL::Vector axis;
  const double moved = (asked.p - verified.p).Norm(), turned = (verified.M.Inverse() * asked.M).GetRotAngle(axis);
  if (moved > tolerances_.goal_position || turned > tolerances_.goal_angle)
    return leave("the goal moved since the verification (registration changed?) by " + number(moved) + " m and " +
                 number(turned) + " rad", result);
  planning::PlanResult path;
  const std::string blocked = recheck(start, start_poses, goal, path);
  if (blocked.empty()) {
    path.message = "the path verified with the procedure (" + path.message + "; start " + number(off) +
                   " m or rad from the walk's)";
  } else {
    // Not from where the robots are (e.g. a redundant robot a few micrometres off the walk's
    // start resolves its redundancy otherwise near a singular pose, or the other robot is in the
    // way): a search from here to the walk's goal, verified densely by the planner, which must
    // end where the walk ended, so that the rest of the walk holds as it does after any step;
    // after the walk's last step nothing follows (the follow-on is checked as always).
    path = checker_.planPath(start, goal);
    if (!path.solved())
      return leave(blocked + "; a search from where it is: " + planning::toString(path.status) + ": " + path.message,
                   result);
    const double end = apart(path.joint_waypoints.back(), next.result.joint_waypoints.back());
    if (end > tolerances_.start && !(ends_walk_ && paths_.size() == 1))
      return leave(blocked + "; a search from where it is ends " + number(end) +
                       " (m or rad) from the joints where the walk ended the step (at most " +
                       number(tolerances_.start) + ")",
                   result);
    path.message = "a new path to the verified goal (" + path.message + ", ending " + number(end) +
                   " m or rad from the walk's end): " + blocked;
  }
  result = std::move(path);
  paths_.pop_back();
  names_.pop_back();
  return true;
}

}  // namespace cobra::task
