#pragma once
/// @file
/// The thesis' I-SUR Robot Bridge (§4.5.7): its update reads and writes a shared memory block
/// only; a local stand-alone server (IsurUdpServer: a thread of this component when `run_server`
/// is set, or the `cobra-isur-server` program) keeps that block in step with the robot
/// controller over UDP.

#include <cstdint>
#include <memory>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/bridges/comm_watchdog.hpp"
#include "cobra/bridges/isur_udp_server.hpp"
#include "cobra/core/component.hpp"

namespace cobra::bridges {

/// Bridge component. Every update: a new desJointPosition or desCartPose becomes the command in
/// shared memory (when both arrive in one update, the pose wins: it is read last); the latest
/// valid state in shared memory is published on the meas* ports, and published again every
/// update while no newer one comes. `e_comm_timeout` when no new valid state came for `timeout`
/// seconds (counted from start), `e_comm_restored` at the first one after that. The controller
/// solves a Cartesian command with the continuity rule (kinematics::ContinuousIk: the solution on
/// the IK branch of its current joint command, within its joint velocity limits over one period)
/// and reports a refusal in the state: `e_ik_discontinuity` when a command was refused by that
/// rule, `e_ik_failed` when the IK could not solve it (each once per refusal episode), then
/// `e_ik_solved` at the first state after that in which the command is no longer held. Rejected
/// datagrams are counted per reason by the server: see the operations `rejectedCount` and
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
  void publish();
  void reportCartesianStatus(std::uint16_t flags);

  core::InputPort<KDL::Frame> des_cart_pose_{
      "desCartPose",
      "desired needle-tip pose, robot base frame; the controller refuses (e_ik_discontinuity) a pose not reachable on "
      "the current IK branch within its joint velocity limits over one period, and holds",
      "m"};
  core::InputPort<KDL::JntArray> des_joints_{"desJointPosition", "desired joints q1..q3 (m), q4..q8 (rad)", "m, rad"};
  core::OutputPort<KDL::Frame> meas_cart_pose_{"measCartPose", "measured needle-tip pose, robot base frame", "m"};
  core::OutputPort<KDL::JntArray> meas_joints_{"measJointPosition", "measured joints q1..q3 (m), q4..q8 (rad)",
                                               "m, rad"};
  core::OutputPort<KDL::Wrench> meas_wrench_{"measWrench", "wrist F/T sensor (AtiNano17), sensor frame", "N, N·m"};

  core::Property<std::string> shm_name_{"shm_name", "/cobra_isur", "",
                                        "POSIX shared memory segment shared with the I-SUR server"};
  core::Property<int> joints_{"joints", 8, "1", "joint count of the robot (I-SUR puncturing: 8)"};
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
  std::uint64_t last_version_ = 0;
  bool have_state_ = false;
  bool refusing_ = false;            // the controller holds a refused Cartesian command
  bool told_failed_ = false;         // e_ik_failed emitted in this refusal episode
  bool told_discontinuity_ = false;  // e_ik_discontinuity emitted in this refusal episode
  isur::State state_;
  isur::Command command_;
  KDL::JntArray q_in_, q_out_;
  KDL::Frame pose_out_;
  KDL::Wrench wrench_out_;
};

}  // namespace cobra::bridges
