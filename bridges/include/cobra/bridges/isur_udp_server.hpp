#pragma once
/// @file
/// The I-SUR side of thesis §4.5.7: the robot bridge reads and writes a shared memory block, and
/// a local stand-alone server keeps that block in step with the robot controller over UDP. This
/// file holds the block and the server; the server runs on its own thread, here or in the
/// `cobra-isur-server` executable.

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "cobra/bridges/isur_protocol.hpp"
#include "cobra/bridges/receive_counters.hpp"
#include "cobra/bridges/seqlock.hpp"
#include "cobra/bridges/shared_memory.hpp"
#include "cobra/bridges/socket.hpp"

namespace cobra::bridges {

/// The shared memory block between ISURRobotBridge (writes `command` and `actuation`, reads
/// `state`) and IsurUdpServer (reads `command` and `actuation`, writes `state` and `counters`).
/// One writer per field.
struct IsurSharedBlock {
  static constexpr std::uint64_t kLayoutTag = 0x4953555200020001ULL;  // "ISUR", block layout 2 (protocol 2)
  std::atomic<std::uint64_t> layout;
  Seqlock<isur::Command> command;       ///< latest desired joints / poses, from the bridge
  Seqlock<isur::Actuation> actuation;   ///< latest tool actuation request, from the bridge
  Seqlock<isur::State> state;           ///< latest valid measured state, from the server
  ReceiveCounters counters;             ///< state datagrams by outcome, from the server
  std::atomic<std::uint64_t> commands_sent;  ///< command datagrams sent, from the server
};

struct IsurUdpServerOptions {
  std::string shm_name = "/cobra_isur";    ///< shared memory segment (POSIX name)
  std::string bind_host = "127.0.0.1";     ///< local address to receive states on
  std::uint16_t bind_port = 0;             ///< local port (0: ephemeral, see local())
  std::string controller_host = "127.0.0.1";
  std::uint16_t controller_port = 0;       ///< where commands go; must be set (> 0)
  std::uint16_t joints = 8;                ///< joint count of valid states (I-SUR puncturing: 8, suturing: 14)
  std::uint16_t tools = 1;                 ///< tool count of valid states, 1..isur::kMaxTools (suturing: 2)
  double command_period = 0.002;           ///< s, > 0: the latest command is re-sent this often (UDP loses)
  double max_delay = 0.05;                 ///< s, >= 0: states delayed more than this are rejected (0: no check)
  double resync_after = 0.5;               ///< s, > 0: without a valid state this long, accept any sequence
                                           ///< number again (the controller may have restarted)
};

/// The local stand-alone server. Not real-time itself (it makes system calls); it decouples the
/// robot bridge's update from the network. It sends a new command at once and repeats the latest
/// one every command_period (UDP may lose it); it sends a new actuation request at once and repeats
/// it every command_period until a valid state acknowledges it (the controller handles each
/// request number once, so a repeat never actuates twice).
class IsurUdpServer {
 public:
  /// Opens the shared memory and binds the socket. @throws std::runtime_error naming what failed
  /// (bad option, address in use, shared memory of another layout).
  explicit IsurUdpServer(IsurUdpServerOptions options);
  ~IsurUdpServer();
  IsurUdpServer(const IsurUdpServer&) = delete;
  IsurUdpServer& operator=(const IsurUdpServer&) = delete;

  void start();
  void stop();
  /// The address states are received on.
  Endpoint local() const { return socket_.local(); }
  const ReceiveCounters& counters() const noexcept { return block_->counters; }
  const IsurUdpServerOptions& options() const noexcept { return options_; }

 private:
  void run() noexcept;
  void receiveAll(std::int64_t now_ns) noexcept;
  void send(const isur::Command& command) noexcept;

  IsurUdpServerOptions options_;
  SharedBlock<IsurSharedBlock> block_;
  UdpSocket socket_;
  Endpoint controller_;
  wire::LatenessFilter lateness_;
  std::atomic<bool> running_{false};
  std::thread thread_;
  std::uint32_t sequence_ = 0;
  std::int64_t last_valid_ns_ = 0;
  std::uint32_t acknowledged_request_ = 0;  // the last valid state's actuation_request
  std::array<std::uint8_t, isur::kMaxFrameSize> out_{};
};

/// Nanoseconds on the steady clock (the timestamp every cobra sender puts in its frames).
std::int64_t steadyNanoseconds() noexcept;

}  // namespace cobra::bridges
