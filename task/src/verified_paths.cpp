#include "cobra/task/verified_paths.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace cobra::task {
namespace {

KDL::Frame& tool(planning::DualPose& pair, std::size_t arm) { return arm == 0 ? pair.first : pair.second; }
const KDL::Frame& tool(const planning::DualPose& pair, std::size_t arm) { return arm == 0 ? pair.first : pair.second; }

/// How far apart two frames are: m, and rad about any axis.
std::pair<double, double> apart(const KDL::Frame& a, const KDL::Frame& b) {
  KDL::Vector axis;
  return {(a.p - b.p).Norm(), (b.M.Inverse() * a.M).GetRotAngle(axis)};
}

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

void VerifiedPaths::assign(std::vector<CheckedPath> paths, std::vector<std::string> names) {
  paths_ = std::move(paths);
  std::reverse(paths_.begin(), paths_.end());  // the next at the back
  names_ = std::move(names);
  names_.resize(paths_.size());
  std::reverse(names_.begin(), names_.end());
  assigned_ = paths_.size();
  current_.reset();
  left_.clear();
}

bool VerifiedPaths::leave(const std::string& why, planning::PlanResult& result) {
  left_ = "left the verified procedure at planned step " + std::to_string(assigned_ - paths_.size() + 1) + " of " +
          std::to_string(assigned_) + " (" + names_.back() + "): " + why + "; verify the procedure again";
  paths_.clear();
  names_.clear();
  current_.reset();
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
  if (current_.has_value() && alternative == current_->alternative) {
    const auto [moved, turned] = apart(tool(goal, arm_), tool(current_->goal, arm_));
    if (moved <= tolerances_.goal_position && turned <= tolerances_.goal_angle) {
      // The step just followed asked again (a retry after a reaction, from wherever the robot
      // was held): a search from where it is to that verified goal, verified densely by the
      // planner from the real state; the next step is checked again from where it ends.
      result = checker_.planPath(start, goal);
      result.message = "the verified goal of " + current_name_ + " again from where the robot is: " + result.message;
      return true;
    }
  }
  if (paths_.empty()) return false;
  const CheckedPath& next = paths_.back();
  if (next.start.size() != start.size()) return leave("the scene's joints changed", result);
  const auto [off, off_angle] = apart(tool(start_poses, arm_), tool(next.result.waypoints.front(), arm_));
  if (off > tolerances_.start_position || off_angle > tolerances_.start_angle)
    return leave("the tool is " + number(off) + " m and " + number(off_angle) +
                     " rad from where the verification started this step (at most " +
                     number(tolerances_.start_position) + " m and " + number(tolerances_.start_angle) + " rad)",
                 result);
  if (alternative != next.alternative) {
    // Another goal alternative than the walk took from here: the run takes the walk's, whose way
    // was verified (a search may find a way to this one that was not).
    result = refusal("not the goal alternative the procedure's verification took from here (it took alternative " +
                     std::to_string(next.alternative + 1) + ")");
    return true;
  }
  const auto [moved, turned] = apart(tool(goal, arm_), tool(next.goal, arm_));
  if (moved > tolerances_.goal_position || turned > tolerances_.goal_angle)
    return leave("the goal moved since the verification (registration changed?) by " + number(moved) + " m and " +
                 number(turned) + " rad", result);
  planning::PlanResult path;
  const std::string blocked = recheck(start, start_poses, goal, path);
  if (blocked.empty()) {
    path.message = "the path verified with the procedure (" + path.message + "; the tool " + number(off) + " m and " +
                   number(off_angle) + " rad from the walk's start)";
  } else {
    // Not from where the robots are (e.g. a redundant robot whose joints differ from the walk's
    // at the same tool pose, its redundancy resolved otherwise near a singular pose, or the other
    // robot in the way): a search from here to the walk's goal, verified densely by the planner
    // from the real state (the next step is checked again from where it ends).
    path = checker_.planPath(start, goal);
    if (!path.solved())
      return leave(blocked + "; a search from where it is: " + planning::toString(path.status) + ": " + path.message,
                   result);
    path.message = "a new path to the verified goal (" + path.message + "): " + blocked;
  }
  result = std::move(path);
  current_ = std::move(paths_.back());
  current_name_ = std::move(names_.back());
  paths_.pop_back();
  names_.pop_back();
  return true;
}

}  // namespace cobra::task
