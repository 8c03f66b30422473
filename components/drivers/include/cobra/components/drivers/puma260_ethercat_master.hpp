#pragma once
/// @file
/// The Puma 260 EtherCAT master (thesis §6.2.1, Fig. 6.4) as a component: a thin adapter around
/// cobra::fieldbus::Puma260Master on a cobra::fieldbus::Cia402Bus found by name.

#include <kdl/jntarray.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cobra/core/component.hpp"
#include "cobra/fieldbus/puma260_master.hpp"

namespace cobra::components {

/// Bridge (the thesis calls it a Driver). Needs a periodic activity: its period is the bus cycle.
///
/// Properties: `bus` (the EtherCAT backend, core::BackendRegistry<fieldbus::Cia402Bus>:
/// `sim:<component>` for the simulated drives of that sim-world component, e.g. a
/// SimulatedPuma260; a SOEM backend would register its own scheme, and moving to hardware changes
/// this property only), `control_mode` ("position", "velocity" or "torque": what Operative commands),
/// `nest_position` and `ready_position` (6 joint angles, rad), `move_speed` (rad/s, peak joint
/// speed of the nest/ready moves), `position_tolerance` (rad), `joint_lower`/`joint_upper` (rad;
/// default: kinematics::Puma260Solver's limits), `max_velocity` (rad/s), `max_torque` (N·m).
///
/// Operations (void; the answer is an event): `askReady()`, `askNest()` (only from the ready
/// position), `askOperative()` (only from the ready position), `askFaultReset()` (only in Fault);
/// a request the current state does not allow emits `e_request_refused`. `slaveStatus(i)` returns
/// a line about slave i; `busFault()` the expected and received working counter of the last cycle
/// that came back with a wrong one.
///
/// Ports: in `desJointPosition` (rad), `desJointVelocity` (rad/s), `desJointTorque` (N·m), used in
/// Operative according to `control_mode`; out `measJointPosition`, `measJointVelocity`,
/// `measJointTorque`, `currentState` (NotInitialized, Initialized, MovingToNest, NestPosition,
/// MovingToReady, ReadyPosition, Operative, Fault), and `heldJointPosition` (rad): in each cycle
/// in Fault once the quick stop has brought every joint to rest (none moved 1e-4 rad in 0.1 s), the measured
/// joints the robot is held at, for the command chain to re-sync to (KinematicsSolver's
/// heldJointPositions; ARCHITECTURE §7).
///
/// Events: e_initialized, e_ready_reached, e_nest_reached, e_operative, e_drive_fault,
/// e_bus_error (link down), e_bus_fault (a cycle came back with a wrong working counter: every
/// cycle it lasts; the master goes to Fault and quick-stops the drives, see `busFault()`),
/// e_fault_reset, e_command_clamped, e_request_refused, e_command_not_finite (a command sample
/// with a NaN or infinite joint: refused, the last finite command of that port stays the drives'
/// set-point; once per episode, again after a finite sample).
class Puma260EtherCATMaster : public core::Component {
 public:
  explicit Puma260EtherCATMaster(std::string name);
  ~Puma260EtherCATMaster() override;

 protected:
  bool configureHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  void ask(fieldbus::Request request);
  std::string slaveStatus(int slave) const;
  std::string busFault() const;

  core::Property<std::string> bus_{"bus", "", "", "EtherCAT backend: sim:<component>"};
  core::Property<std::string> control_mode_{"control_mode", "position", "", "position, velocity or torque"};
  core::Property<std::vector<double>> nest_{"nest_position", {}, "rad", "6 joint angles of the nest position"};
  core::Property<std::vector<double>> ready_{"ready_position", {}, "rad", "6 joint angles of the ready position"};
  core::Property<double> move_speed_{"move_speed", 0.5, "rad/s", "peak joint speed of the nest and ready moves"};
  core::Property<double> tolerance_{"position_tolerance", 2e-3, "rad", "a move ends when every joint is this close"};
  core::Property<std::vector<double>> lower_{"joint_lower", {}, "rad", "6 lower joint limits"};
  core::Property<std::vector<double>> upper_{"joint_upper", {}, "rad", "6 upper joint limits"};
  core::Property<double> max_velocity_{"max_velocity", 2.0, "rad/s", "velocity-mode commands are clamped to it"};
  core::Property<double> max_torque_{"max_torque", 20.0, "N·m", "torque-mode commands are clamped to it"};
  core::InputPort<KDL::JntArray> des_position_{"desJointPosition", "desired joint positions (Operative, position mode)",
                                               "rad"};
  core::InputPort<KDL::JntArray> des_velocity_{"desJointVelocity",
                                               "desired joint velocities (Operative, velocity mode)", "rad/s"};
  core::InputPort<KDL::JntArray> des_torque_{"desJointTorque", "desired joint torques (Operative, torque mode)", "N·m"};
  core::OutputPort<KDL::JntArray> meas_position_{"measJointPosition", "measured joint positions", "rad"};
  core::OutputPort<KDL::JntArray> meas_velocity_{"measJointVelocity", "measured joint velocities", "rad/s"};
  core::OutputPort<KDL::JntArray> meas_torque_{"measJointTorque", "measured joint torques", "N·m"};
  core::OutputPort<KDL::JntArray> held_position_{
      "heldJointPosition",
      "in each cycle in Fault once every joint is at rest: the measured joints the robot is held at",
      "rad"};
  core::OutputPort<core::TaskState> current_state_{"currentState", "state of the master (thesis Fig. 6.4)", ""};

  std::shared_ptr<fieldbus::Cia402Bus> bus_device_;
  std::optional<fieldbus::Puma260Master> master_;
  fieldbus::JointCommands commands_;
  fieldbus::MasterState published_ = fieldbus::MasterState::NotInitialized;  // last on currentState
  KDL::JntArray scratch_{6}, out_{6};
  fieldbus::JointVector rest_position_{};  // rad: in Fault, where the joints have stayed for still_time_
  double still_time_ = 0.0;                // s
  bool refusing_non_finite_ = false;       // a command sample was not finite; e_command_not_finite told
};

}  // namespace cobra::components
