#pragma once
/// @file
/// The far end of the I-SUR UDP path for tests and simulation: a stand-in for the I-SUR robot
/// controller that runs the simulated robot (sim::ServoRobot driven in joint space, or in
/// Cartesian space through sim::CartesianServo and kinematics::IsurPuncturingSolver) with an
/// AtiNano17 wrist sensor (sim::ForceTorqueSensor), in real time on its own thread, and speaks
/// the protocol of isur_protocol.hpp: it takes command datagrams and sends a state datagram
/// every period to the server's address. Simulation only: the bridge's own end is IsurUdpServer
/// (cobra/bridges/isur_udp_server.hpp).

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
#include "cobra/sim/ft_sensor.hpp"
#include "cobra/sim/servo.hpp"

namespace cobra::bridges {

struct IsurSimControllerOptions {
  std::string bind_host = "127.0.0.1";
  std::uint16_t bind_port = 0;           ///< 0: ephemeral (see local())
  std::string server_host = "127.0.0.1";
  std::uint16_t server_port = 0;         ///< where states go; 0: to the sender of the last valid command
  double period = 0.002;                 ///< s, > 0: simulation step and state period
  double servo_time_constant = 0.02;     ///< s: first-order lag of every joint
  double max_velocity = 1.0;             ///< rad/s or m/s per joint
  double encoder_counts = 1 << 20;       ///< counts per revolution / metre
  std::uint64_t seed = 1;                ///< F/T sensor noise
};

/// Simulated I-SUR controller. The joints start at the middle of their limits. Until it knows
/// where to send states (a server_port, or a first valid command) it sends nothing. A Cartesian
/// command is solved with the continuity rule (sim::CartesianServo, kinematics::ContinuousIk)
/// from the current joint command, dt = period: a command on another IK branch or more than
/// max_velocity · period away on some joint is refused (the robot holds its command; the states
/// carry kCartesianHeld | kCartesianDiscontinuous), as is one the IK cannot solve (kCartesianHeld).
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

  /// The wrench the environment applies on the wrist sensor (N, N·m, sensor frame).
  void setExternalWrench(const KDL::Wrench& wrench);
  /// false: the controller keeps simulating but sends nothing (a silent link).
  void setSending(bool sending) { sending_.store(sending); }
  /// The last joint command applied to the servo (clamped to the limits; rad / m).
  KDL::JntArray commandedJoints() const;
  /// True joint positions of the simulated robot (rad / m).
  KDL::JntArray jointPositions() const;
  /// Command datagrams by outcome.
  const ReceiveCounters& counters() const noexcept { return counters_; }
  std::uint64_t statesSent() const noexcept { return states_sent_.load(); }

 private:
  void run() noexcept;
  void receiveAll() noexcept;
  void stepAndSend(double dt) noexcept;

  IsurSimControllerOptions options_;
  UdpSocket socket_;
  Endpoint server_;
  bool server_known_ = false;  // touched by the controller thread only
  kinematics::IsurPuncturingSolver solver_;
  std::unique_ptr<sim::ServoRobot> robot_;
  std::unique_ptr<sim::CartesianServo> cartesian_;
  sim::ForceTorqueSensor sensor_;
  mutable std::mutex mutex_;  // guards the simulation against the test-facing accessors
  KDL::Wrench external_ = KDL::Wrench::Zero();
  bool held_ = false;           // the last Cartesian command was refused
  bool discontinuous_ = false;  // ... by the continuity rule
  std::uint32_t sequence_ = 0;
  ReceiveCounters counters_;
  std::atomic<std::uint64_t> states_sent_{0};
  std::atomic<bool> sending_{true};
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace cobra::bridges
