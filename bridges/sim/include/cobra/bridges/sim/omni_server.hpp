#pragma once
/// @file
/// A stand-in for the stand-alone Omni application (thesis §4.5.9) for tests and simulation: a
/// TCP server speaking omni_protocol.hpp that wraps sim::HapticMaster held by the simulated hand.
/// Simulation only: the bridge's own end is OmniClient (cobra/bridges/omni_tcp.hpp).

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include <kdl/frames.hpp>

#include "cobra/bridges/omni_protocol.hpp"
#include "cobra/bridges/receive_counters.hpp"
#include "cobra/bridges/socket.hpp"
#include "cobra/bridges/stream_framer.hpp"
#include "cobra/sim/haptic.hpp"

namespace cobra::bridges {

struct OmniSimServerOptions {
  std::string bind_host = "127.0.0.1";
  std::uint16_t bind_port = 0;         ///< 0: ephemeral (see local())
  double period = 0.001;               ///< s, > 0: simulation step and state period (the Omni runs at 1 kHz)
  sim::HapticMasterModel model;
};

/// Simulated Omni application: one client at a time; sends a State frame every period (stylus
/// position = the device's quantised reading, orientation identity: the simulated Omni is
/// translation only; twist = its velocity) and renders the force of every valid WrenchCommand.
class OmniSimServer {
 public:
  /// @throws std::runtime_error (socket) or std::invalid_argument (model).
  explicit OmniSimServer(OmniSimServerOptions options);
  ~OmniSimServer();
  OmniSimServer(const OmniSimServer&) = delete;
  OmniSimServer& operator=(const OmniSimServer&) = delete;

  void start();
  void stop();
  Endpoint local() const { return listener_.local(); }

  void setHandTarget(const KDL::Vector& target);  ///< m, device frame
  void setButtons(std::uint32_t buttons) { buttons_.store(buttons); }
  void setSending(bool sending) { sending_.store(sending); }
  /// Closes the current connection (the client must reconnect).
  void dropClient() { drop_requested_.store(true); }
  KDL::Vector commandedForce() const;  ///< N: last valid WrenchCommand force
  KDL::Vector position() const;        ///< m: true stylus position
  const ReceiveCounters& counters() const noexcept { return counters_; }
  std::uint64_t accepted() const noexcept { return accepted_.load(); }  ///< connections accepted

 private:
  void run() noexcept;
  void receive(int fd, bool& alive) noexcept;
  void stepAndSend(int fd, double dt, bool& alive) noexcept;

  OmniSimServerOptions options_;
  TcpListener listener_;
  sim::HapticMaster master_;
  mutable std::mutex mutex_;
  KDL::Vector commanded_force_ = KDL::Vector::Zero();
  StreamFramer framer_{omni::kMagic, omni::kVersion, omni::kMaxPayload};
  wire::LatenessFilter lateness_;
  ReceiveCounters counters_;
  std::uint32_t sequence_ = 0;
  std::atomic<std::uint32_t> buttons_{0};
  std::atomic<bool> sending_{true};
  std::atomic<bool> drop_requested_{false};
  std::atomic<std::uint64_t> accepted_{0};
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace cobra::bridges
