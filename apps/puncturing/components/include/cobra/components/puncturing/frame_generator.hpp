#pragma once
/// @file
/// The Puncturing Frame Generator (thesis §4.5.5): the framework's StateTableFrameGenerator
/// (components/task) with the puncturing task's datums. It loads the preoperative information,
/// the cryoablation plan and the ultrasound probe plan (apps/puncturing/README.md), and on request
/// publishes the goal poses of both robots for the current state of the task, mapped from the
/// abdomen frame A to the task (world) frame.

#include <optional>
#include <string>

#include <kdl/frames.hpp>

#include "cobra/components/task/state_table_frame_generator.hpp"
#include "cobra/core/request.hpp"
#include "cobra/puncturing/plan.hpp"

namespace cobra::components {

/// Interface (besides StateTableFrameGenerator's: `state_table_file`, `currentTaskState`,
/// `desiredPoses`, `goalPoses`, `askCurrentGoal()`, `lastFailure()`; arm 0 = needle, arm 1 =
/// probe, measured on `needleMeasPose` and `USMeasPose`):
/// - properties `preoperative_info_file`, `cryo_plan_file`, `US_pose_plan_file` (paths, read and
///   cross-checked at configure: a bad file refuses configure with "component 'X': FILE:LINE:
///   message"), `arm` ("needle" or "probe": the robot whose chart calls this instance; both
///   instances publish the pair, `arm` names the instance in messages and the log);
/// - input port `abdomenFrame` (KDL.Frame, m: A in the world frame; until a sample arrives, the
///   nominal `abdomen` pose of the preoperative file);
/// - output port `needleTarget` (KDL.Frame, m: the current needle's planned tip pose in the world,
///   the NeedleInsertionMonitor's targetPose), written at every askCurrentGoal while a needle is left;
/// - operations `nextNeedle()` (a void request answered in the next step, before a goal asked in
///   the same step), `currentNeedle()` (int, 0-based), `needleCount()` (int), `plannedTarget(i)`
///   (KDL.Frame: needle i's planned tip pose in the world with the latest abdomenFrame);
/// - events `e_needle_selected` (nextNeedle moved to a planned needle) and `e_all_needles_done`
///   (nextNeedle moved past the last needle), besides e_goal_ready and e_no_data.
///
/// Datums (state table): entry / target = the current needle's tip frame at its skin entry /
/// at its target, probe = its planned probe pose (all three in frame A, mapped with
/// abdomenFrame; next_entry, next_target, next_probe: the same of the needle after the current
/// one, which a room_for_* leaves out after the last needle), then moved `offset` m along the
/// tool's own z axis; `hold` and the table's poses as every table.
///
/// Real time: as StateTableFrameGenerator's; nextNeedle allocates nothing.
class PuncturingFrameGenerator : public StateTableFrameGenerator {
 public:
  explicit PuncturingFrameGenerator(std::string name);

  /// The plan loaded at configure (nullptr before).
  const puncturing::PuncturingPlan* plan() const { return plan_ ? &*plan_ : nullptr; }

 protected:
  bool configureTask() override;
  void readTaskInputs() override;
  void stepTask() override;
  Outcome resolveTaskDatum(const task::Datum& datum, std::size_t arm, KDL::Frame& pose, const char*& why) override;

 private:
  /// The request nextNeedle: on to the next planned needle (e_all_needles_done after the last).
  void advanceNeedle();
  KDL::Frame plannedTarget(int index);
  /// Reads abdomenFrame (keeps the last sample, or the nominal pose) and returns it.
  const KDL::Frame& abdomen();

  core::Property<std::string> preoperative_file_{"preoperative_info_file", "", "",
                                                 "preoperative information (abdomen, tumour, forbidden regions)"};
  core::Property<std::string> cryo_plan_file_{"cryo_plan_file", "", "", "cryoablation plan: the needles, frame A"};
  core::Property<std::string> probe_plan_file_{"US_pose_plan_file", "", "", "probe pose of each needle, frame A"};
  core::Property<std::string> arm_{"arm", "needle", "", "the robot whose chart calls this instance: needle or probe"};

  core::InputPort<KDL::Frame> abdomen_frame_{"abdomenFrame", "abdomen frame A in the world frame", "m"};
  core::OutputPort<KDL::Frame> needle_target_{"needleTarget", "the current needle's planned tip pose, world", "m"};

  std::optional<puncturing::PuncturingPlan> plan_;
  int needle_ = 0;
  KDL::Frame abdomen_ = KDL::Frame::Identity();
  core::PendingRequest next_needle_request_;  // answered in the next step
};

}  // namespace cobra::components
