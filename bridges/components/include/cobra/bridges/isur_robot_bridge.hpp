#pragma once
/// @file
/// The thesis' I-SUR Robot Bridge (§4.5.7): its update reads and writes a shared memory block
/// only; a local stand-alone server (IsurUdpServer: a thread of this component when `run_server`
/// is set, or the `cobra-isur-server` program) keeps that block in step with the robot
/// controller over UDP.

#include <array>
#include <cstdint>
#include <memory>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/bridges/comm_watchdog.hpp"
#include "cobra/bridges/isur_udp_server.hpp"
#include "cobra/core/component.hpp"
#include "cobra/core/event.hpp"

namespace cobra::bridges {

/// Bridge component for the I-SUR with `tools` tools: 1, the puncturing robot (the needle), or 2,
/// the suturing robot of thesis §5.3 (Right: the Endo Stitch on the 4-DOF arm, Left: the gripper's
/// stick on the 6-DOF arm; the interface of the simulated robot SimulatedISURSuturingRobot, so a
/// deployment swaps one for the other by the component type).
///
/// Ports, tools = 1: in `desCartPose`, out `measCartPose`, `measWrench`. tools = 2: in
/// `desRightCartPose`, `desLeftCartPose`, out `measRightCartPose`, `measLeftCartPose`,
/// `measRightWrench`, `measLeftWrench`, in `inputEvents` (event port), out `endoStitchActuations`
/// (int). Both: in `desJointPosition`, out `measJointPosition`. The ports of tools = 1 exist from
/// construction; configuring with tools = 2 replaces them by the two-tool set (and back): connect
/// the per-tool ports after configuring.
///
/// Every update: a new desJointPosition or desCart*Pose becomes the command in shared memory (when
/// both arrive in one update, the poses win: they are read last; with two tools, the command carries
/// every tool commanded since the last joint command, the others keep the pose of the robot's
/// current joint command); the latest valid state in shared memory is published on the meas* ports,
/// and published again every update while no newer one comes. `e_comm_timeout` when no new valid
/// state came for `timeout` seconds (counted from start), `e_comm_restored` at the first one after
/// that. The controller solves a Cartesian command with the continuity rule (the solution on the
/// IK branch of its current joint command, within its joint velocity limits over one period; see
/// IsurSimController for the two-tool robot) and reports a refusal in the state: `e_ik_discontinuity`
/// when a command was refused by that rule, `e_ik_failed` when the IK could not solve it (each once
/// per refusal episode), then `e_ik_solved` at the first state after that in which the command is
/// no longer held.
///
/// Held poses (out, robot base frame, m; `heldCartPose`, or `heldRightCartPose` and
/// `heldLeftCartPose` with two tools): in each update with a state that reports a refused command,
/// and in each update while the state is timed out (e_comm_timeout until e_comm_restored), the
/// latest measured pose of every tool: where the robot is held. Wired to the held-pose inputs of
/// the producers of the commands (VariableAdmittance's heldPose, CartesianTrajectoryGenerator's
/// heldPose_i), they re-sync to it and the next command starts where the robot is (ARCHITECTURE
/// §7). The controller holds its last accepted command, which the measured pose settles on within
/// its servo's lag; the state carries no commanded pose, so the measured one is sent, again in each
/// held state until a command is accepted.
///
/// Endo Stitch (tools = 2): the event `actuate_event` on inputEvents sends a ToolActuation request
/// for tool 0 through the server; when a state's completed count increments, endoStitchActuations
/// (completed actuations since start) is written and `e_endo_stitch_actuated` emitted. A request
/// while an actuation runs or a request is unanswered, or one the controller refuses, gives
/// `e_endo_stitch_busy` (as the simulated robot).
///
/// Rejected datagrams are counted per reason by the server: see the operations `rejectedCount` and
/// `acceptedCount`. Real time: the update is allocation-free and never blocks (seqlock reads
/// with a bounded number of retries).
class ISURRobotBridge : public core::Component {
 public:
  explicit ISURRobotBridge(std::string name);
  ~ISURRobotBridge() override;

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  int rejectedCount(std::string reason);
  int acceptedCount();
  int serverPort();
  void registerToolPorts(unsigned tools);
  void readCommands(IsurSharedBlock& block) noexcept;
  void readActuationRequests(IsurSharedBlock& block) noexcept;
  void reportActuations() noexcept;
  void publish();
  void reportCartesianStatus(std::uint16_t flags);

  core::InputPort<KDL::Frame> des_cart_pose_{
      "desCartPose",
      "desired needle-tip pose, robot base frame; the controller refuses (e_ik_discontinuity) a pose not reachable on "
      "the current IK branch within its joint velocity limits over one period, and holds",
      "m"};
  core::OutputPort<KDL::Frame> meas_cart_pose_{"measCartPose", "measured needle-tip pose, robot base frame", "m"};
  core::OutputPort<KDL::Wrench> meas_wrench_{"measWrench", "wrist F/T sensor (AtiNano17), sensor frame", "N, N·m"};
  core::InputPort<KDL::Frame> des_right_pose_{
      "desRightCartPose", "desired Endo Stitch tip pose, robot base frame (refused and held as desCartPose)", "m"};
  core::InputPort<KDL::Frame> des_left_pose_{
      "desLeftCartPose", "desired stick tip pose (gripper arm), robot base frame (refused and held as desCartPose)",
      "m"};
  core::OutputPort<KDL::Frame> meas_right_pose_{"measRightCartPose", "measured Endo Stitch tip pose, robot base frame",
                                                "m"};
  core::OutputPort<KDL::Frame> meas_left_pose_{"measLeftCartPose", "measured stick tip pose, robot base frame", "m"};
  core::OutputPort<KDL::Wrench> meas_right_wrench_{
      "measRightWrench", "Endo Stitch arm F/T sensor (AtiNano43), sensor frame", "N, N·m"};
  core::OutputPort<KDL::Wrench> meas_left_wrench_{"measLeftWrench", "gripper arm F/T sensor (AtiNano17), sensor frame",
                                                  "N, N·m"};
  core::OutputPort<KDL::Frame> held_cart_pose_{
      "heldCartPose",
      "while the controller holds (a refused command) or the state is timed out: the measured needle-tip pose, robot "
      "base frame",
      "m"};
  core::OutputPort<KDL::Frame> held_right_pose_{
      "heldRightCartPose", "while held (as heldCartPose): the measured Endo Stitch tip pose, robot base frame", "m"};
  core::OutputPort<KDL::Frame> held_left_pose_{
      "heldLeftCartPose", "while held (as heldCartPose): the measured stick tip pose, robot base frame", "m"};
  core::InputPort<core::Event> input_events_{"inputEvents", "requests: actuate_event actuates the Endo Stitch", ""};
  core::OutputPort<int> actuations_out_{"endoStitchActuations", "completed Endo Stitch actuations since start", "1"};
  core::InputPort<KDL::JntArray> des_joints_{"desJointPosition",
                                             "desired joints q1..q3 (m), q4.. (rad): 8 (one tool) or 14 (two tools)",
                                             "m, rad"};
  core::OutputPort<KDL::JntArray> meas_joints_{"measJointPosition", "measured joints q1..q3 (m), q4.. (rad)",
                                               "m, rad"};

  core::Property<std::string> shm_name_{"shm_name", "/cobra_isur", "",
                                        "POSIX shared memory segment shared with the I-SUR server"};
  core::Property<int> joints_{"joints", 8, "1", "joint count of the robot (I-SUR puncturing: 8, suturing: 14)"};
  core::Property<int> tools_{"tools", 1, "1",
                             "tool count: 1 (puncturing: the needle) or 2 (suturing: Right Endo Stitch, Left stick)"};
  core::Property<std::string> actuate_event_{"actuate_event", "e_actuate_endo_stitch", "",
                                             "event on inputEvents that actuates the Endo Stitch (tools = 2)"};
  core::Property<double> timeout_{"timeout", 0.1, "s", "without a new valid state this long: e_comm_timeout"};
  core::Property<bool> run_server_{"run_server", false, "",
                                   "run the I-SUR UDP server as a thread of this process (else: cobra-isur-server)"};
  core::Property<std::string> controller_host_{"controller_host", "127.0.0.1", "",
                                               "robot controller address (run_server only)"};
  core::Property<int> controller_port_{"controller_port", 0, "1", "robot controller UDP port (run_server only)"};
  core::Property<int> server_port_{"server_port", 0, "1", "local UDP port for states; 0: any (run_server only)"};
  core::Property<double> max_delay_{"max_delay", 0.05, "s",
                                    "states delayed more than this are rejected, 0: no check (run_server only)"};

  std::unique_ptr<SharedBlock<IsurSharedBlock>> block_;
  std::unique_ptr<IsurUdpServer> server_;
  CommWatchdog watchdog_;
  unsigned tools_registered_ = 1;  // the tool count whose ports are registered
  std::array<core::InputPort<KDL::Frame>*, isur::kMaxTools> des_poses_{};
  std::array<core::OutputPort<KDL::Frame>*, isur::kMaxTools> meas_poses_{};
  std::array<core::OutputPort<KDL::Wrench>*, isur::kMaxTools> meas_wrenches_{};
  std::array<core::OutputPort<KDL::Frame>*, isur::kMaxTools> held_poses_{};
  bool timed_out_ = false;  // no fresh state for `timeout` (e_comm_timeout told, e_comm_restored not yet)
  core::BoundedString<63> actuate_name_;
  std::uint64_t last_version_ = 0;
  bool have_state_ = false;
  bool refusing_ = false;            // the controller holds a refused Cartesian command
  bool told_failed_ = false;         // e_ik_failed emitted in this refusal episode
  bool told_discontinuity_ = false;  // e_ik_discontinuity emitted in this refusal episode
  std::uint32_t request_ = 0;        // the last actuation request sent (0: none since start)
  bool request_open_ = false;        // sent and not yet acknowledged by a state
  bool have_count_ = false;          // actuation_base_ is known (a state came since start)
  std::uint32_t actuation_base_ = 0;  // the controller's completed count at the first state since start
  std::uint32_t actuations_seen_ = 0;
  isur::State state_;
  isur::Command command_;
  KDL::JntArray q_in_, q_out_;
  std::array<KDL::Frame, isur::kMaxTools> pose_out_;
  std::array<KDL::Wrench, isur::kMaxTools> wrench_out_;
};

}  // namespace cobra::bridges
