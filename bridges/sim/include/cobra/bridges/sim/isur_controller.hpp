#pragma once
/// @file
/// The far end of the I-SUR UDP path for tests and simulation: a stand-in for the I-SUR robot
/// controller that runs the simulated robot — the puncturing setup (one tool, 8 joints,
/// kinematics::IsurPuncturingSolver, an AtiNano17 at the wrist) or the suturing setup of thesis
/// §5.3 (two tools, 14 joints, kinematics::IsurSuturingSolver; tool 0 the Endo Stitch with an
/// AtiNano43 (§5.3.2), tool 1 the gripper's stick with an AtiNano17) — as a sim::ServoRobot driven in
/// joint or Cartesian space, with one sim::ForceTorqueSensor per tool, in real time on its own
/// thread, and speaks the protocol of isur_protocol.hpp: it takes command datagrams and sends a
/// state datagram every period to the server's address. Simulation only: the bridge's own end is
/// IsurUdpServer (cobra/bridges/isur_udp_server.hpp).

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/bridges/isur_protocol.hpp"
#include "cobra/bridges/receive_counters.hpp"
#include "cobra/bridges/socket.hpp"
#include "cobra/kinematics/isur.hpp"
#include "cobra/kinematics/isur_continuity.hpp"
#include "cobra/sim/ft_sensor.hpp"
#include "cobra/sim/servo.hpp"

namespace cobra::bridges {

struct IsurSimControllerOptions {
  std::string bind_host = "127.0.0.1";
  std::uint16_t bind_port = 0;           ///< 0: ephemeral (see local())
  std::string server_host = "127.0.0.1";
  std::uint16_t server_port = 0;         ///< where states go; 0: to the sender of the last valid command
  std::uint16_t tools = 1;               ///< 1: puncturing setup (8 joints), 2: suturing setup (14 joints)
  /// rad / m, one per joint; empty: the middle of the joint limits. With two tools, a Cartesian
  /// command of the current poses is a zero step only from joints the split IK gives back for
  /// their own poses (its redundancy rule fixes the macro and elbow shares); from others the first
  /// Cartesian command may move a joint more than the velocity bound allows, and is refused.
  std::vector<double> initial_joints;
  double period = 0.002;                 ///< s, > 0: simulation step and state period
  double servo_time_constant = 0.02;     ///< s: first-order lag of every joint
  double max_velocity = 1.0;             ///< rad/s or m/s per joint
  double encoder_counts = 1 << 20;       ///< counts per revolution / metre
  double actuation_time = 0.3;           ///< s, > 0: one Endo Stitch actuation (suturing setup)
  std::uint64_t seed = 1;                ///< F/T sensor noise
};

/// Simulated I-SUR controller. Until it knows where to send states (a server_port, or a first
/// valid command) it sends nothing.
///
/// Cartesian commands are solved from the current joint command (the servo's set point), dt =
/// period, and refused — the robot holds its command; the states carry kCartesianHeld, plus
/// kCartesianDiscontinuous when the rule below refused it — when:
///  - one tool: the continuity rule (sim::CartesianServo, kinematics::ContinuousIk) refuses it (another
///    IK branch, or a joint more than max_velocity · period away), or the IK cannot solve it;
///  - two tools: the same rule for the split IK of §5.4.1 (kinematics::ContinuousIsurSuturingIk:
///    each sub-structure, the macro + Endo Stitch arm and the gripper arm, on the IK branch of the
///    current joint command, every joint within max_velocity · period), or the split IK cannot solve
///    it. A tool whose mask bit is clear keeps the pose of the current joint command.
///
/// A ToolActuation of tool 0 on the suturing setup starts an Endo Stitch actuation of
/// actuation_time s (states carry kActuating); when it ends the completed count in the states
/// increments. A request while one is in progress, of another tool or on the puncturing setup (no
/// actuator) is refused (kActuationRefused with its request number). Each request number is handled
/// once: the server's repeats change nothing.
class IsurSimController {
 public:
  /// @throws std::runtime_error (bad option, socket) or std::invalid_argument (sim models).
  explicit IsurSimController(IsurSimControllerOptions options);
  ~IsurSimController();
  IsurSimController(const IsurSimController&) = delete;
  IsurSimController& operator=(const IsurSimController&) = delete;

  void start();
  void stop();
  Endpoint local() const { return socket_.local(); }

  /// The wrench the environment applies on tool `tool`'s sensor (N, N·m, sensor frame).
  void setExternalWrench(const KDL::Wrench& wrench, std::size_t tool = 0);
  /// false: the controller keeps simulating but sends nothing (a silent link).
  void setSending(bool sending) { sending_.store(sending); }
  /// The last joint command applied to the servo (clamped to the limits; rad / m).
  KDL::JntArray commandedJoints() const;
  /// True joint positions of the simulated robot (rad / m).
  KDL::JntArray jointPositions() const;
  /// Completed Endo Stitch actuations.
  std::uint32_t actuations() const;
  /// Command datagrams by outcome.
  const ReceiveCounters& counters() const noexcept { return counters_; }
  std::uint64_t statesSent() const noexcept { return states_sent_.load(); }

 private:
  void run() noexcept;
  void receiveAll() noexcept;
  void apply(const isur::Command& command) noexcept;
  void commandPoses(const isur::Command& command) noexcept;
  void actuate(const isur::Actuation& actuation) noexcept;
  void stepAndSend(double dt) noexcept;
  bool forward(const KDL::JntArray& q, KDL::Frame& tool0, KDL::Frame& tool1) noexcept;

  IsurSimControllerOptions options_;
  UdpSocket socket_;
  Endpoint server_;
  bool server_known_ = false;  // touched by the controller thread only
  std::unique_ptr<kinematics::IsurPuncturingSolver> puncturing_;  // tools = 1
  std::unique_ptr<kinematics::IsurSuturingSolver> suturing_;      // tools = 2
  std::unique_ptr<kinematics::ContinuousIsurSuturingIk> suturing_continuity_;  // tools = 2
  std::unique_ptr<sim::ServoRobot> robot_;
  std::unique_ptr<sim::CartesianServo> cartesian_;  // tools = 1
  std::vector<sim::ForceTorqueSensor> sensors_;     // one per tool
  mutable std::mutex mutex_;  // guards the simulation against the test-facing accessors
  std::vector<KDL::Wrench> external_;  // per tool
  KDL::JntArray solution_;             // tools = 2: the split IK's answer
  bool held_ = false;           // the last Cartesian command was refused
  bool discontinuous_ = false;  // ... by the continuity rule
  std::uint32_t last_request_ = 0;   // the last actuation request handled
  bool request_refused_ = false;     // ... and whether it was refused
  double actuation_left_ = 0.0;      // s of the running actuation, 0: none
  std::uint32_t actuations_ = 0;     // completed
  std::uint32_t sequence_ = 0;
  ReceiveCounters counters_;
  std::atomic<std::uint64_t> states_sent_{0};
  std::atomic<bool> sending_{true};
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace cobra::bridges
