#pragma once
/// @file
/// DoorSim: the simulated world of the door task (thesis §2.2, Fig. 2.5), a Bridge component
/// that is to the task what a robot bridge is to a real cell: commands in, measurements out.
/// Package "cobra_door" (registerDoorPackage).
///
/// A one-axis arm approaches a door handle; its gripper grasps the handle when it is within
/// `grip_tolerance` and the grip command is above 0.5; a torque on the grasped handle turns it
/// against a spring; past `latch_angle` the latch releases and a pull force opens the door (a
/// rotating mass with viscous damping). A force or torque command older than `command_timeout`
/// counts as zero, as a real drive's watchdog would do, so stopping the component that sends it
/// stops the action. Needs a periodic activity (1 ms in door.lua); updateHook allocates nothing.
///
/// Non-finite commands: a NaN or infinite sample on any command port is refused, as a drive's
/// set-point check would: the door goes on with that port's last finite command (which then
/// times out as above), and emits e_command_not_finite once per episode (again after a finite
/// sample on that port). The `applied*` outputs carry what it applies each step (always finite):
/// the commands the task watches reaching the robot.

#include "cobra/core/component.hpp"

namespace cobra::components {

class DoorSim : public core::Component {
 public:
  explicit DoorSim(std::string name);

 protected:
  bool startHook() override;
  void updateHook() override;

 private:
  /// The value of a command port, or 0 when it has not been refreshed within command_timeout.
  /// `value` and `stamp` change only on a new finite sample; a non-finite one is refused (see above).
  double freshCommand(core::InputPort<double>& port, double& value, std::chrono::nanoseconds& stamp, bool& refused);
  /// Takes a new sample of `port` into `value` when it is finite (true); a non-finite one is
  /// refused (e_command_not_finite once per episode, `refused` set until a finite sample).
  bool takeFinite(core::InputPort<double>& port, double& value, bool& refused) noexcept;

  core::InputPort<double> arm_target_{"armTarget", "where the arm should go (distance from its home)", "m"};
  core::InputPort<double> grip_command_{"gripCommand", "close the gripper when > 0.5", "1"};
  core::InputPort<double> handle_torque_{"handleTorque", "torque on the grasped handle", "N·m"};
  core::InputPort<double> pull_force_{"pullForce", "force pulling the grasped handle", "N"};
  core::OutputPort<double> arm_position_{"armPosition", "distance of the arm from its home", "m"};
  core::OutputPort<double> gripped_{"gripped", "1 when the handle is grasped, else 0", "1"};
  core::OutputPort<double> handle_angle_{"handleAngle", "rotation of the handle", "rad"};
  core::OutputPort<double> door_angle_{"doorAngle", "opening of the door", "rad"};
  core::OutputPort<double> applied_arm_target_{"appliedArmTarget", "the arm target applied (last finite sample)", "m"};
  core::OutputPort<double> applied_grip_{"appliedGripCommand", "the grip command applied (0 when stale)", "1"};
  core::OutputPort<double> applied_torque_{"appliedHandleTorque", "the handle torque applied (0 when stale)", "N·m"};
  core::OutputPort<double> applied_force_{"appliedPullForce", "the pull force applied (0 when stale)", "N"};

  core::Property<double> handle_position_{"handle_position", 0.5, "m", "distance of the handle from the arm's home"};
  core::Property<double> arm_time_constant_{"arm_time_constant", 0.1, "s", "first-order lag of the arm"};
  core::Property<double> grip_tolerance_{"grip_tolerance", 0.01, "m", "how close to the handle the gripper must be"};
  core::Property<double> handle_stiffness_{"handle_stiffness", 2.0, "N·m/rad", "spring returning the handle"};
  core::Property<double> handle_damping_{"handle_damping", 0.2, "N·m·s/rad", "viscous damping of the handle"};
  core::Property<double> latch_angle_{"latch_angle", 0.7, "rad", "handle rotation that releases the latch"};
  core::Property<double> door_inertia_{"door_inertia", 2.0, "kg·m²", "inertia of the door about its hinge"};
  core::Property<double> door_damping_{"door_damping", 4.0, "N·m·s/rad", "viscous damping of the hinge"};
  core::Property<double> lever_arm_{"lever_arm", 0.8, "m", "distance from the hinge to the handle"};
  core::Property<double> door_max_angle_{"door_max_angle", 1.6, "rad", "the door stops there"};
  core::Property<double> command_timeout_{"command_timeout", 0.05, "s", "older force/torque commands count as 0"};

  std::chrono::nanoseconds last_step_{0};
  std::chrono::nanoseconds grip_stamp_{0}, torque_stamp_{0}, force_stamp_{0};
  double arm_target_value_ = 0.0, grip_value_ = 0.0, torque_value_ = 0.0, force_value_ = 0.0;
  double arm_ = 0.0, handle_ = 0.0, door_ = 0.0, door_rate_ = 0.0;
  bool gripped_state_ = false;
  // Per command port: a non-finite sample was refused and not followed by a finite one yet.
  bool arm_refused_ = false, grip_refused_ = false, torque_refused_ = false, force_refused_ = false;
};

}  // namespace cobra::components
