#pragma once
/// @file
/// The thesis' Kinematics Solver component (§6.2.4): forward and inverse kinematics of a serial
/// robot, by data flow or on demand, with the KDL and the closed-form solvers interchangeable.

#include <memory>
#include <string>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/core/component.hpp"
#include "cobra/kinematics/continuity.hpp"
#include "cobra/kinematics/kinematics_solver.hpp"

namespace cobra::components {

/// Calculation component. Properties: `robot` ("ur5", "puma260" or "dh": the `dh_table`
/// property, 7 numbers per joint: a (m), alpha (rad), d (m), theta offset (rad), type (0 revolute,
/// 1 prismatic), lower and upper limit (rad or m)), `solver` ("closed_form", "kdl_nr",
/// "kdl_lma"; "dh" robots have no closed form; configure refuses kdl_lma in a process where KDL's
/// LMA cannot run, e.g. one that loads Debian's OMPL first: kinematics::kdlLmaConflict says why),
/// `base_frame` and `tool_frame` (m),
/// `max_joint_velocity` (rad/s, m/s per joint; empty: the UR5's 3.14 rad/s, required for the
/// others), `period` (s; 0: the activity's period) and `speed_scaling` (0.001..1, default 1,
/// changed at run time: a reduced mode; the continuity rule allows that fraction of
/// max_joint_velocity).
///
/// Data flow: `jointPositions` (in) -> `cartPose` (out), forward kinematics on every update with
/// new joints; `desCartPose` (in, event port) -> `desJointPositions` (out): inverse kinematics
/// with the continuity rule of kinematics::ContinuousIk, published only when the solution is
/// valid (thesis §6.2.4) and continuous. The reference ("current joints") is the last accepted
/// solution while commands keep coming (a desCartPose in the previous update), otherwise the last
/// measured joints (or, before any are measured, the last solution; the very first command, with
/// neither, is only solved). A command is refused when the solution nearest the reference on its
/// IK branch differs from it by more than max_joint_velocity · period on some joint, or only
/// another branch reaches it: `e_ik_discontinuity` (once per refusal episode); a command the
/// solver cannot solve: `e_ik_failed` (once per episode); the reason is in `lastIkStatus()`. The
/// first accepted command after refusals emits `e_ik_solved`. In each update that refuses a
/// command, `heldCartPose` (out, world frame, m) carries the pose the robot holds: the forward
/// kinematics of the last accepted solution (its set-point), or of the measured joints when
/// commands had paused (the reference the refused command was judged from). Wired to the
/// held-pose inputs of whatever produces desCartPose (VariableAdmittance's heldPose,
/// CartesianTrajectoryGenerator's heldPose_i), the producers re-sync to it and the next command
/// starts where the robot is (ARCHITECTURE §7). `heldJointPositions` (in, rad or m): joints
/// something else holds the robot at (a drive's quick stop: Puma260EtherCATMaster's
/// heldJointPosition); each sample becomes the reference of the next command and is passed on
/// as heldCartPose, so the command chain re-syncs to a stopped robot as it does to a refusal
/// (the desCartPose samples of that update, made before their producers knew, are dropped).
/// On demand: operations `forward(q)` and `inverse(pose, seed)` (no continuity rule: planning
/// use), which throw the status' name.
/// Real time: the closed-form solvers and KDL's NR_JL/LMA as cobra builds them allocate nothing.
class KinematicsSolverComponent : public core::Component {
 public:
  explicit KinematicsSolverComponent(std::string name);
  ~KinematicsSolverComponent() override;

 protected:
  bool configureHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  KDL::Frame forwardOnDemand(KDL::JntArray q);
  KDL::JntArray inverseOnDemand(KDL::Frame pose, KDL::JntArray seed);
  kinematics::KinematicsSolver& solver();

  core::Property<std::string> robot_{"robot", "ur5", "", "ur5, puma260 or dh (the dh_table property)"};
  core::Property<std::string> solver_kind_{"solver", "closed_form", "", "closed_form, kdl_nr or kdl_lma"};
  core::Property<std::vector<double>> dh_table_{
      "dh_table", {}, "m, rad", "for robot = dh: a, alpha, d, theta, type (0 revolute, 1 prismatic), lower, upper per joint"};
  core::Property<KDL::Frame> base_frame_{"base_frame", KDL::Frame::Identity(), "m", "pose of the robot base in the world"};
  core::Property<KDL::Frame> tool_frame_{"tool_frame", KDL::Frame::Identity(), "m", "pose of the tool in the flange frame"};
  core::Property<std::vector<double>> max_joint_velocity_{
      "max_joint_velocity", {}, "rad/s, m/s",
      "velocity limit per joint for the continuity rule (empty: the UR5's 3.14 rad/s; required for puma260 and dh)"};
  core::Property<double> period_{"period", 0.0, "s",
                                 "time a command has to be reached in (continuity rule); 0: the activity's period"};
  core::Property<double> speed_scaling_{"speed_scaling", 1.0, "1",
                                        "fraction of max_joint_velocity a command may use (0.001..1; run time)"};

  core::InputPort<KDL::JntArray> joint_positions_{"jointPositions", "measured joint positions", "rad or m"};
  core::OutputPort<KDL::Frame> cart_pose_{"cartPose", "tool pose for jointPositions (world frame)", "m"};
  core::InputPort<KDL::Frame> des_cart_pose_{
      "desCartPose",
      "desired tool pose (world frame); refused (e_ik_discontinuity) unless reachable on the current IK branch within "
      "max_joint_velocity x period on every joint",
      "m"};
  core::OutputPort<KDL::Frame> held_cart_pose_{
      "heldCartPose",
      "in each update refusing a command (or held by heldJointPositions): the pose the robot holds (world frame)",
      "m"};
  core::InputPort<KDL::JntArray> held_joint_positions_{
      "heldJointPositions", "joints something else holds the robot at (a drive's quick stop), passed on as heldCartPose",
      "rad or m"};
  core::OutputPort<KDL::JntArray> des_joint_positions_{
      "desJointPositions", "joint positions reaching desCartPose, continuous from the current joints (none when refused)",
      "rad or m"};

  std::unique_ptr<kinematics::KinematicsSolver> kinematics_;
  std::unique_ptr<kinematics::ContinuousIk> continuity_;
  KDL::JntArray q_, measured_, solution_, candidate_;  // sized at configure: updates allocate nothing
  KDL::Frame pose_;
  bool have_measured_ = false;
  bool have_solution_ = false;
  bool streaming_ = false;          // a desCartPose came in the previous update
  bool refusing_ = false;           // the last command was refused
  bool told_failed_ = false;        // e_ik_failed emitted in this refusal episode
  bool told_discontinuity_ = false; // e_ik_discontinuity emitted in this refusal episode
  kinematics::IkStatus last_status_ = kinematics::IkStatus::Ok;
  /// Writes heldCartPose: the pose of joints `q` (nothing when their forward kinematics fails).
  void publishHeld(const KDL::JntArray& q) noexcept;
};

/// The thesis' two interchangeable components (§6.2.4) as two type names: the same interface, the
/// KDL solver (Newton-Raphson with joint limits: KDL's Levenberg-Marquardt cannot run in a process
/// with the planning library, see kinematics::kdlLmaConflict) or the closed form by default. Either
/// can be set to the other.
class KdlKinematicsSolver : public KinematicsSolverComponent {
 public:
  explicit KdlKinematicsSolver(std::string name);
};
class ClosedFormKinematicsSolver : public KinematicsSolverComponent {
 public:
  explicit ClosedFormKinematicsSolver(std::string name);
};

}  // namespace cobra::components
