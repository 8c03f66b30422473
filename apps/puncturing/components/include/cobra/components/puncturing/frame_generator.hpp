#pragma once
/// @file
/// The Puncturing Frame Generator (thesis §4.5.5): a Bridge component that loads the
/// preoperative information, the cryoablation plan, the ultrasound probe plan and a state→data
/// table (apps/puncturing/README.md), and on request publishes the goal poses of both robots for
/// the current state of the task, mapped from the abdomen frame A to the task (world) frame.

#include <array>
#include <optional>
#include <string>

#include <kdl/frames.hpp>

#include "cobra/components/motion/path_type.hpp"
#include "cobra/core/component.hpp"
#include "cobra/core/event.hpp"
#include "cobra/core/request.hpp"
#include "cobra/puncturing/plan.hpp"
#include "cobra/puncturing/plan_goals.hpp"

namespace cobra::components {

/// Interface:
/// - properties `preoperative_info_file`, `cryo_plan_file`, `US_pose_plan_file`,
///   `state_table_file` (paths, read and cross-checked at configure: a bad file refuses
///   configure with "component 'X': FILE:LINE: message"), `arm` ("needle" or "probe": the robot
///   whose chart calls this instance; both instances publish the pair, `arm` names the instance
///   in messages and the log);
/// - input ports `abdomenFrame` (KDL.Frame, m: A in the world frame; until a sample arrives, the
///   nominal `abdomen` pose of the preoperative file), `currentTaskState` (TaskState: the
///   chart's active state), `needleMeasPose`, `USMeasPose` (KDL.Frame, m, world);
/// - output ports `desiredPoses` (TGL.MultiAxisPath, two waypoints [measured pair, goal pair],
///   7 values per arm, arm 0 = needle, arm 1 = probe, as path_type.hpp encodes them: the
///   CartesianTrajectoryGenerator's plannedPath; its goal is the row's first alternative),
///   `goalPoses` (the MotionPlanner's goalPoses: one waypoint per goal alternative of the row,
///   the preferred first; 14 values (the goal pair) for a row without then_* or room_for_*,
///   otherwise 28 + 28 per room_for_*: the goal pair, where the straight motion after it goes
///   (then_*; the goal again for an arm without one), and per room_for_* that arm's later motion
///   as its start pair and end pair with the other arm at its goal; a room_for_* naming a next_*
///   datum is left out after the last needle), `needleTarget` (KDL.Frame, m: the current
///   needle's planned tip pose in the world, the NeedleInsertionMonitor's targetPose);
/// - operations `askCurrentGoal()`, `nextNeedle()` (void requests answered by events),
///   `currentNeedle()` (int, 0-based), `needleCount()` (int), `plannedTarget(i)` (KDL.Frame:
///   needle i's planned tip pose in the world with the latest abdomenFrame), `lastFailure()`
///   (why the last askCurrentGoal answered e_no_data);
/// - events `e_goal_ready` (desiredPoses, goalPoses and needleTarget written), `e_no_data` (no
///   table row for the task state, no task state yet, no measured pose yet, or no needle left;
///   the reason, naming the state and the datum, is in lastFailure() and printed on stderr),
///   `e_needle_selected` (nextNeedle moved to a planned needle) and `e_all_needles_done`
///   (nextNeedle moved past the last needle).
///
/// Datums (state table): entry / target = the current needle's tip frame at its skin entry /
/// at its target, probe = its planned probe pose (all three in frame A, mapped with
/// abdomenFrame; next_entry, next_target, next_probe: the same of the needle after the current
/// one), hold = the arm's measured pose (world), a named pose = a fixed task-frame pose; then
/// moved `offset` m along the tool's own z axis.
///
/// askCurrentGoal and nextNeedle are answered in this component's next step (they only mark the
/// request and wake the activity: core::PendingRequest), so the supervisor that asks spends
/// nothing on them: the table lookup, the frame products and the three port writes run in this
/// component's thread.
///
/// Real time: the answer (a table lookup over the rows, a few frame products) and nextNeedle
/// allocate nothing once the first answer has sized the port connections, when they answer
/// e_goal_ready for a row of one goal without then_* or room_for_*, or e_all_needles_done: the
/// paths are preallocated at configure and refilled in place. A row with alternatives or checks
/// (a planned motion's goal) builds its goalPoses, and answering e_no_data builds the message
/// (both allocate).
class PuncturingFrameGenerator : public core::Component, private puncturing::DatumSource {
 public:
  explicit PuncturingFrameGenerator(std::string name);

  /// The plan and table loaded at configure (nullptr before).
  const puncturing::PuncturingPlan* plan() const { return plan_ ? &*plan_ : nullptr; }
  const puncturing::StateTable& table() const { return table_; }

  /// The request askCurrentGoal (from any thread): answered in the next step.
  void askCurrentGoal();

 protected:
  bool configureHook() override;
  void updateHook() override;

 private:
  enum class Arm { Needle = 0, Probe = 1 };

  /// Publishes the goal of the task state on currentTaskState (or answers e_no_data).
  void answerCurrentGoal();
  /// The request nextNeedle: on to the next planned needle (e_all_needles_done after the last).
  void advanceNeedle();
  KDL::Frame plannedTarget(int index);
  /// Reads abdomenFrame (keeps the last sample, or the nominal pose) and returns it.
  const KDL::Frame& abdomen();
  /// The pose `datum` names for `arm` (DatumSource: the table's evaluator asks).
  Outcome resolve(const puncturing::Datum& datum, std::size_t arm, KDL::Frame& pose, const char*& why) override;
  void noData(const std::string& reason);
  /// Writes desiredPoses [measured pair, goal_pair_], goalPoses = `goal` and emits e_goal_ready.
  void publish(const trajectory::MultiAxisPath& goal);

  core::Property<std::string> preoperative_file_{"preoperative_info_file", "", "",
                                                 "preoperative information (abdomen, tumour, forbidden regions)"};
  core::Property<std::string> cryo_plan_file_{"cryo_plan_file", "", "", "cryoablation plan: the needles, frame A"};
  core::Property<std::string> probe_plan_file_{"US_pose_plan_file", "", "", "probe pose of each needle, frame A"};
  core::Property<std::string> state_table_file_{"state_table_file", "", "", "state -> goal datum of each arm"};
  core::Property<std::string> arm_{"arm", "needle", "", "the robot whose chart calls this instance: needle or probe"};

  core::InputPort<KDL::Frame> abdomen_frame_{"abdomenFrame", "abdomen frame A in the world frame", "m"};
  core::InputPort<core::TaskState> task_state_{"currentTaskState", "the task chart's active state", ""};
  core::InputPort<KDL::Frame> needle_meas_{"needleMeasPose", "measured needle tip pose, world", "m"};
  core::InputPort<KDL::Frame> us_meas_{"USMeasPose", "measured probe pose, world", "m"};
  core::OutputPort<trajectory::MultiAxisPath> desired_poses_{
      "desiredPoses", "[measured pair, goal pair]: needle then probe, x y z qx qy qz qw each, world", "m"};
  core::OutputPort<trajectory::MultiAxisPath> goal_poses_{
      "goalPoses", "goal alternatives, one waypoint each: the goal pair (needle then probe, x y z qx qy qz qw each, "
      "world), with the checks of its row (then_*, room_for_*) after it", "m"};
  core::OutputPort<KDL::Frame> needle_target_{"needleTarget", "the current needle's planned tip pose, world", "m"};

  std::optional<puncturing::PuncturingPlan> plan_;
  puncturing::StateTable table_;
  int needle_ = 0;
  KDL::Frame abdomen_ = KDL::Frame::Identity();
  std::array<KDL::Frame, 2> measured_;
  std::array<bool, 2> have_measured_{false, false};
  std::array<KDL::Frame, 2> goal_pair_;  // the goal pair of the row's first alternative
  core::TaskState state_;
  trajectory::MultiAxisPath desired_, goal_;  // preallocated: 2 x 14 and 1 x 14 values
  puncturing::GoalFailure failure_;
  std::string last_failure_;
  core::PendingRequest goal_request_, next_needle_request_;  // answered in the next step
};

}  // namespace cobra::components
