#pragma once
/// @file
/// A robot's Motion Planner with the whole procedure verified before its first motion:
/// the framework's MotionPlannerComponent (components/planning), plus verifyProcedure(), which
/// walks every motion state both charts will run for the plan and the registration
/// (cobra::puncturing::procedureSteps, the state table's goals) with the same planner's options
/// and seed (task/planned_walk.hpp), from the robots' measured joints.

#include <memory>
#include <optional>
#include <string>

#include <kdl/frames.hpp>

#include "cobra/components/planning/motion_planner_component.hpp"
#include "cobra/components/puncturing/navigation_plan.hpp"
#include "cobra/core/request.hpp"
#include "cobra/puncturing/plan.hpp"
#include "cobra/task/planned_walk.hpp"
#include "cobra/task/verified_paths.hpp"
#include "cobra/types/point_list.hpp"

namespace cobra::components {

/// Interface (besides MotionPlannerComponent's):
/// - properties `preoperative_info_file`, `cryo_plan_file`, `US_pose_plan_file`,
///   `state_table_file` (the Frame Generators' files: read and cross-checked at configure, a bad
///   file refuses with "FILE:LINE: message"), `arm` ("needle" or "probe": the robot whose chart
///   asks this planner, whose planned steps it follows after the walk), `other_max_vel` (m/s per
///   Cartesian axis) and `other_max_ang_vel` (rad/s): the other robot's trajectory generator's
///   limits, with which its steps are checked (this planner's own max_vel is its robot's),
///   `verify_walk` (true; false: verifyProcedure answers e_procedure_verified at once without
///   walking, and plans search as the MotionPlanner's: only to show what the walk prevents);
/// - input port `abdomenFrame` (KDL.Frame, m: the registered abdomen frame A in the world; until a
///   sample arrives, the preoperative nominal pose);
/// - operations `verifyProcedure()` (void, answered in this component's next step:
///   `e_procedure_verified` or `e_procedure_refused`), `lastRefusal()` (one line: the needle, the
///   task state with its table line, the datum and why, e.g. "needle n2 (2 of 2), task state
///   'root.InsertingNeedles.MoveToSkin.Approach' (state_table.txt:38), needle=entry-0.02: invalid
///   goal: ..."; "" when the last verification passed or none ran), `lastVerification()` (what
///   the last one found: steps, validity checks);
/// - events `e_procedure_verified`, `e_procedure_refused` (the line also on stderr and on out-port
///   `refusal`, string, for a navigation peer);
/// - `plan_source` ("files" or "navigation"): with navigation the plan comes from in-port `plan`
///   (Geometry.PointList, frame A, m) and the registration from `abdomenFrame`, as the Frame
///   Generator takes them (navigation_plan.hpp: the same plan from the same messages, the first
///   plan with the registration then); only `preoperative_info_file` and `state_table_file` are
///   read at configure; verifyProcedure waits for both (and the joints), and refuses what the
///   Frame Generator refuses (a plan validate() refuses, a registration beyond the tolerance).
///
/// After a verified procedure, the plans of this arm follow the walk's paths, one per planned
/// step in the walk's order, and never search their own way while one is left
/// (task::VerifiedPaths, with its default FollowTolerances: the tool within 0.02 m and 0.02 rad
/// of the walk's start of the step, the walk's goal alternative at its goal within 2 mm and
/// 0.01 rad, every waypoint and edge checked again from the robots' real joints, else a search
/// from there to that goal; the step just followed asked again, a retry after a reaction, is
/// searched from where the robot is to its verified goal). Leaving the
/// verified procedure fails this plan and every later one (e_plan_failed, lastPlanResult "left
/// the verified procedure at planned step k of n (task state 'S', needle N): why; verify the
/// procedure again") until verifyProcedure() passes again. Once every verified path was followed,
/// plans search as the MotionPlanner does. A refused verification, and configure, forget the
/// paths: a reconfigured planner follows nothing.
///
/// Runs in updateHook, like planning: a non-real-time activity (MotionPlannerComponent's).
class PuncturingMotionPlanner : public MotionPlannerComponent {
 public:
  /// The robots of the scene by arm (needle, probe), resolved at configure.
  static constexpr const char* kRobotNames[2] = {"isur", "ur5"};

  explicit PuncturingMotionPlanner(std::string name);

 protected:
  bool configureHook() override;
  void updateHook() override;
  bool reusePath(const planning::JointState& start, const planning::DualPose& start_poses,
                 const planning::DualPose& goal, std::size_t alternative, planning::PlanResult& result) override;

 private:
  /// The walk of the whole procedure from the measured joints; emits its verdict.
  void verify();
  /// `seconds`: the walk's wall time (for the line on stderr).
  void refuseProcedure(const std::string& line, double seconds = 0.0);
  /// Forgets the verified paths (a refusal, a configure).
  void forgetPaths();
  /// Navigation: reads the plan and registration until both came, then takes the plan (or
  /// refuses). True when the walk may go on.
  bool takeNavigatedPlan();

  core::Property<std::string> preoperative_file_{"preoperative_info_file", "", "",
                                                 "preoperative information (abdomen, tumour, forbidden regions)"};
  core::Property<std::string> cryo_plan_file_{"cryo_plan_file", "", "", "cryoablation plan: the needles, frame A"};
  core::Property<std::string> probe_plan_file_{"US_pose_plan_file", "", "", "probe pose of each needle, frame A"};
  core::Property<std::string> table_file_{"state_table_file", "", "", "the Frame Generators' state table"};
  core::Property<std::string> arm_{"arm", "needle", "", "the robot whose chart asks this planner: needle or probe"};
  core::Property<std::string> plan_source_{"plan_source", "files", "",
                                           "where the cryoablation plan and registration come from: files or navigation"};
  core::Property<double> other_max_vel_{"other_max_vel", 0.05, "m/s",
                                        "max velocity per Cartesian axis of the other robot's trajectory generator"};
  core::Property<double> other_max_ang_vel_{"other_max_ang_vel", 0.5, "rad/s",
                                            "max angular velocity of the other robot's trajectory generator"};
  core::Property<bool> walk_{"verify_walk", true, "",
                             "false: verifyProcedure answers e_procedure_verified without walking and nothing is "
                             "followed (only to show what the verification prevents)"};
  core::InputPort<KDL::Frame> abdomen_frame_{"abdomenFrame", "abdomen frame A in the world frame", "m"};
  core::InputPort<types::PointList> plan_in_{"plan", "navigation: the needles' entry and target points, frame A", "m"};
  core::OutputPort<std::string> refusal_{"refusal", "why the procedure was refused, one line", ""};

  std::optional<puncturing::PuncturingPlan> plan_;
  std::optional<task::StateTable> table_;
  std::optional<puncturing::PreoperativeInfo> preoperative_;  // navigation: read at configure
  puncturing_navigation::NavigationInputs navigation_;       // until the plan is taken
  KDL::Frame abdomen_ = KDL::Frame::Identity();
  core::PendingRequest verify_request_;
  bool verify_pending_ = false;  // asked, waiting for the robots' measured joints
  std::string last_refusal_, last_verification_;
  std::size_t arm_index_ = 0;    // 0 needle, 1 probe
  std::size_t robot_index_ = 0;  // this arm's robot in the scene (kRobotNames)
  std::unique_ptr<task::VerifiedPaths> follower_;  // the verified walk's paths of this arm
};

}  // namespace cobra::components
