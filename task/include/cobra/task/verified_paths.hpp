#pragma once
/// @file
/// The run following a verified procedure (procedure_walk.hpp, planned_walk.hpp): one robot's
/// planned steps take the paths the walk verified, in the walk's order, instead of searching
/// again (a search from nearly the same joints may take another way, which was not verified).
/// Each query must be the walk's: from where the walk started the step, to the goal alternative it
/// took, at the goal it verified; the path is checked again with the other robot where it really
/// is. Leaving the verified procedure fails that plan and every later one until it is verified
/// again. Library code: planning and task, no runtime. Units: m, rad.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "cobra/planning/motion_planner.hpp"
#include "cobra/task/planned_walk.hpp"

namespace cobra::task {

/// How near a run's query must be to the walk's for the walk's path to be followed.
struct FollowTolerances {
  /// The moving robot's tool at the query's start against where the walk started the step (m; rad
  /// about any axis). The walk assumes every motion primitive reaches its table goal; the
  /// contact-ended ones (a descent to the skin, a press, a puncture) end where the contact stops
  /// them, a few mm off, and tracking leaves the rest. Its joints may differ more: a redundant
  /// robot tracking its commands every millisecond resolves its redundancy unlike the walk's
  /// coarser steps; the path is checked again from the robot's real joints.
  double start_position = 0.02;
  double start_angle = 0.02;
  /// The moving robot's goal against the walk's (m; rad about any axis): the same table row
  /// resolved with the same registration gives the same goal, but a `hold` goal is where the robot
  /// really is, off the walk's by its tracking (the puncturing runs' worst: 1.2 mm, 0.3 deg);
  /// beyond, the goal moved (the registration or the plan changed). The last segment into the
  /// goal asked is checked again.
  double goal_position = 0.002;
  double goal_angle = 0.01;
};

class VerifiedPaths {
 public:
  /// `robot`: the scene's robot the paths move (the other's joints are held where they are);
  /// `arm`: its tool in a DualPose (0: first, 1: second); `options`: that robot's planner's (the
  /// edges are walked at its verify density and speeds, a search uses its seed). `validator`
  /// is borrowed and must outlive this.
  VerifiedPaths(planning::StateValidator& validator, const planning::PlannerOptions& options, std::size_t robot,
                std::size_t arm, FollowTolerances tolerances = {});
  VerifiedPaths(const VerifiedPaths&) = delete;
  VerifiedPaths& operator=(const VerifiedPaths&) = delete;

  /// The walk's paths of this robot in its order, each named for messages ("task state 'S',
  /// needle n2 (2 of 3)"). Forgets having left.
  void assign(std::vector<CheckedPath> paths, std::vector<std::string> names);

  /// A plan query of this robot from its joints `start` (poses `start_poses`) to `goal`, goal
  /// alternative `alternative` (0-based). False: no verified path is left (none was assigned, or
  /// every one was followed): search as without a verification. True with `result`:
  /// - the walk's path, when the tool starts within the start tolerances of the walk's start, the
  ///   alternative is the walk's and its goal within the goal tolerances, and every waypoint and
  ///   edge (walked as MotionPlanner::checkFollowOn does, the first from `start`) passes with the
  ///   robots where they are; failing those re-checks, a search from `start` to that goal (the
  ///   planner's dense verification from the real state; the next step is checked again from
  ///   where it ends);
  /// - the step followed last asked again (its alternative, its goal within the goal tolerances:
  ///   a retry after a reaction, from wherever the robot was held): a search from `start` to it;
  /// - NoSolution "not the goal alternative the procedure's verification took from here (it took
  ///   alternative k)" for another alternative (the verified one may follow);
  /// - otherwise NoSolution "left the verified procedure at planned step k of n (NAME): why;
  ///   verify the procedure again", and the same for every later query until assign().
  bool follow(const planning::JointState& start, const planning::DualPose& start_poses,
              const planning::DualPose& goal, std::size_t alternative, planning::PlanResult& result);

  std::size_t remaining() const { return paths_.size(); }
  /// Why the run left the verified procedure ("": it did not).
  const std::string& left() const { return left_; }

 private:
  bool leave(const std::string& why, planning::PlanResult& result);
  /// "" with `path` when the next path passes from `start` with the other robot where it is.
  std::string recheck(const planning::JointState& start, const planning::DualPose& start_poses,
                      const planning::DualPose& goal, planning::PlanResult& path);

  planning::StateValidator& validator_;
  planning::MotionPlanner checker_;
  std::size_t robot_, arm_;
  FollowTolerances tolerances_;
  std::vector<CheckedPath> paths_;  // not yet followed, the next first
  std::vector<std::string> names_;
  std::size_t assigned_ = 0;
  std::optional<CheckedPath> current_;  // the path followed last: its step may be asked again
  std::string current_name_;
  std::string left_;
};

}  // namespace cobra::task
