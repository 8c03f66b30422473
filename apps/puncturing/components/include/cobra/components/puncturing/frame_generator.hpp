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

#include "cobra/components/puncturing/navigation_plan.hpp"
#include "cobra/components/task/state_table_frame_generator.hpp"
#include "cobra/core/request.hpp"
#include "cobra/puncturing/plan.hpp"
#include "cobra/types/point_list.hpp"

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
/// Navigation (`plan_source` = "navigation"; "files", the default, reads the three files): the
/// cryoablation plan comes from in-port `plan` (Geometry.PointList, m, frame A: points
/// `<needle>.entry`, `<needle>.target`, from the IgtlBridge) and the registration from
/// `abdomenFrame`; only `preoperative_info_file` is read (the cryo and probe plan files are not).
/// The first plan with the registration then is taken once both have come (later ones change
/// nothing: the procedure is verified for these): the probe plan is computed (probePlan()), the
/// whole validated and the registration checked against the preoperative one
/// (navigation_plan.hpp). Operation `awaitNavigation()` (a request answered in a later step):
/// `e_navigation_received` once the plan is taken (its description on stderr and in
/// `navigationStatus()`), `e_navigation_refused` (why: `navigationStatus()`, also written on
/// out-port `refusal`, string, for the navigation peer), or `e_navigation_timeout` after
/// `navigation_timeout` s without them (naming what did not come). With files it answers
/// e_navigation_received at once.
///
/// Real time: as StateTableFrameGenerator's; nextNeedle allocates nothing. Taking a navigated
/// plan allocates, once (its needles, probe poses, messages).
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
  /// Reads abdomenFrame (keeps the last sample, or the nominal pose) and returns it; with a
  /// navigated plan, the registration it was taken with.
  const KDL::Frame& abdomen();
  bool navigated() const { return plan_source_() == "navigation"; }
  /// Navigation: takes the plan once it and the registration have come; answers awaitNavigation.
  void stepNavigation();
  void answerNavigation(const char* event, std::string status);

  core::Property<std::string> preoperative_file_{"preoperative_info_file", "", "",
                                                 "preoperative information (abdomen, tumour, forbidden regions)"};
  core::Property<std::string> cryo_plan_file_{"cryo_plan_file", "", "", "cryoablation plan: the needles, frame A"};
  core::Property<std::string> probe_plan_file_{"US_pose_plan_file", "", "", "probe pose of each needle, frame A"};
  core::Property<std::string> arm_{"arm", "needle", "", "the robot whose chart calls this instance: needle or probe"};
  core::Property<std::string> plan_source_{"plan_source", "files", "",
                                           "where the cryoablation plan and registration come from: files or navigation"};
  core::Property<double> navigation_timeout_{"navigation_timeout", 120.0, "s",
                                             "awaitNavigation gives up after this long without plan and registration"};

  core::InputPort<KDL::Frame> abdomen_frame_{"abdomenFrame", "abdomen frame A in the world frame", "m"};
  core::OutputPort<KDL::Frame> needle_target_{"needleTarget", "the current needle's planned tip pose, world", "m"};
  core::InputPort<types::PointList> plan_in_{"plan", "navigation: the needles' entry and target points, frame A", "m"};
  core::OutputPort<std::string> refusal_{"refusal", "navigation: why the plan was refused or did not come, one line", ""};

  std::optional<puncturing::PuncturingPlan> plan_;
  int needle_ = 0;
  KDL::Frame abdomen_ = KDL::Frame::Identity();
  core::PendingRequest next_needle_request_;  // answered in the next step
  core::PendingRequest navigation_request_;   // awaitNavigation
  bool awaiting_ = false;                     // awaitNavigation asked, not answered yet
  std::int64_t awaiting_since_ns_ = 0;
  std::optional<puncturing::PreoperativeInfo> preoperative_;  // navigation: read at configure
  puncturing_navigation::NavigationInputs navigation_;  // until the plan is taken
  std::string navigation_status_;             // what was taken, or why not ("" before)
  bool navigation_refused_ = false;
};

}  // namespace cobra::components
