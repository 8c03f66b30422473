#pragma once
/// @file
/// The bridge's end of the Omni TCP path (thesis §4.5.9): `OmniClient`, the service thread of the
/// OmniPhantomBridge that connects to the stand-alone Omni application. Protocol:
/// omni_protocol.hpp. The simulated application (OmniSimServer) is in cobra/bridges/sim/.

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "cobra/bridges/omni_protocol.hpp"
#include "cobra/bridges/receive_counters.hpp"
#include "cobra/bridges/seqlock.hpp"
#include "cobra/bridges/socket.hpp"
#include "cobra/bridges/stream_framer.hpp"

namespace cobra::bridges {

struct OmniClientOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;           ///< the application's TCP port; must be set (> 0)
  double reconnect_period = 0.05;   ///< s, > 0: wait between connection attempts
  double max_delay = 0.05;          ///< s, >= 0: states delayed more than this are rejected (0: no check)
};

/// Keeps a connection to the Omni application, reconnecting after the peer drops. The owner
/// exchanges data with it through the lock-free `state` (written here) and `command` (read here).
class OmniClient {
 public:
  /// @throws std::runtime_error when the options are invalid or the host does not resolve.
  explicit OmniClient(OmniClientOptions options);
  ~OmniClient();
  OmniClient(const OmniClient&) = delete;
  OmniClient& operator=(const OmniClient&) = delete;

  void start();
  void stop();

  Seqlock<omni::State> state;             ///< latest valid state (written by the client thread)
  Seqlock<omni::WrenchCommand> command;   ///< wrench to send (written by the owner, one writer)
  const ReceiveCounters& counters() const noexcept { return counters_; }
  bool connected() const noexcept { return connected_.load(); }
  std::uint64_t connections() const noexcept { return connections_.load(); }  ///< successful connects
  std::uint64_t drops() const noexcept { return drops_.load(); }  ///< connections lost or dropped

 private:
  void run() noexcept;
  bool serve(int fd) noexcept;  // one pass on a live connection; false when it must be closed

  OmniClientOptions options_;
  Endpoint peer_;
  StreamFramer framer_{omni::kMagic, omni::kVersion, omni::kMaxPayload};
  wire::LatenessFilter lateness_;
  ReceiveCounters counters_;
  std::uint32_t sequence_ = 0;
  std::uint64_t sent_version_ = 0;
  std::atomic<bool> connected_{false};
  std::atomic<std::uint64_t> connections_{0};
  std::atomic<std::uint64_t> drops_{0};
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace cobra::bridges
