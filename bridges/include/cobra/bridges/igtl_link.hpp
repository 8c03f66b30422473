#pragma once
/// @file
/// `IgtlLink`: the service thread of the IgtlBridge, one OpenIGTLink TCP connection at a time, as
/// a server (3D Slicer's OpenIGTLinkIF connector or PLUS connects to it) or as a client. All socket
/// I/O happens on its thread; the owner exchanges with it without locks: decoded messages come
/// out of `received` (a core::SpscRing), encoded small messages go in through `outgoing` (another
/// ring), and each image stream through a core::TripleBuffer of one image (only the newest image
/// matters), which this thread encodes: the IMAGE's CRC over up to 64 KiB is not the update's
/// cost. It is built into the components library (it uses core's ring and types::GrayImage).
///
/// Framing: a header (58 bytes) whose version or names are not valid loses the message
/// boundaries, so the connection is closed (counted as bad_header) and the next one is served; a
/// body above `max_body` is skipped byte by byte (oversized); a bad CRC, an unknown type or a
/// malformed body drops that message only. A peer silent for `peer_timeout` is treated as gone:
/// its connection is closed. Messages queued while no peer is connected are discarded.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/bridges/igtl_codec.hpp"
#include "cobra/bridges/socket.hpp"
#include "cobra/core/spsc_ring.hpp"
#include "cobra/core/triple_buffer.hpp"
#include "cobra/types/gray_image.hpp"

namespace cobra::bridges {

struct IgtlLinkOptions {
  bool server = true;             ///< true: listen for one peer at a time; false: connect to host:port
  std::string host = "127.0.0.1"; ///< server: the address to bind ("0.0.0.0": all); client: the peer
  std::uint16_t port = 18944;     ///< TCP port; a server may give 0 (an ephemeral port, see localPort)
  std::size_t max_body = 1 << 20; ///< bytes: bodies above are skipped and counted as oversized
  double peer_timeout = 0.0;      ///< s: a peer silent this long is dropped; 0: never
  double reconnect_period = 0.1;  ///< s, client: wait between connection attempts
  std::vector<std::string> image_devices;  ///< one image stream (triple buffer) per device name
};

/// Why the link (or its owner) dropped a message: the codec's reasons, then the link's and the
/// bridge's own. Names (dropReasonName) are short enough for std::string's inline storage.
enum class DropReason : std::uint8_t {
  None,
  Truncated,      ///< the peer closed in the middle of a message
  BadHeader,      ///< not an OpenIGTLink version 1 or 2 header: the connection was closed
  Oversized,      ///< above max_message_bytes
  BadCrc,
  UnknownType,    ///< a type the bridge does not take (IMAGE, POSITION, ...)
  BadBody,
  QueueFull,      ///< the owner did not take received messages fast enough
  UnknownDevice,  ///< (bridge) no mapping for the message's device
  Unmapped,       ///< (bridge) a request STRING whose text is no mapped key
  SendFull,       ///< (bridge) the outgoing queue was full
  PlanTooLong,    ///< (bridge) a POINT plan of more points than a PointList holds: never cut, dropped
};
inline constexpr std::size_t kDropReasons = 12;
std::string_view dropReasonName(DropReason reason) noexcept;
DropReason toDropReason(igtl::IgtlError error) noexcept;

/// A small encoded message (TRANSFORM, STATUS, STRING) on its way to the link.
struct IgtlOutMessage {
  std::uint32_t size = 0;
  std::array<std::uint8_t, igtl::kHeaderSize + 40 + igtl::kMaxText> bytes{};
};

/// A KDL frame (m) as the codec's 3x4 matrix (m).
inline igtl::Transform toIgtlTransform(const KDL::Frame& f) noexcept {
  igtl::Transform t;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) t.matrix[r][c] = f.M(r, c);
    t.matrix[r][3] = f.p(r);
  }
  return t;
}

/// One image on its way to the link, with the wire timestamp of the update that took it.
struct IgtlImage {
  types::GrayImage image;
  std::uint64_t timestamp = 0;
};

class IgtlLink {
 public:
  static constexpr std::size_t kQueue = 64;  ///< messages each ring holds

  /// A server binds here (so its port is known at once). @throws std::runtime_error naming the
  /// address when it cannot bind or resolve.
  explicit IgtlLink(IgtlLinkOptions options);
  ~IgtlLink();
  IgtlLink(const IgtlLink&) = delete;
  IgtlLink& operator=(const IgtlLink&) = delete;

  void start();
  void stop();
  /// Server: the bound port (the ephemeral one when options.port was 0); client: options.port.
  std::uint16_t localPort() const noexcept { return local_port_; }

  core::SpscRing<igtl::Message> received{kQueue};  ///< link thread -> owner
  core::SpscRing<IgtlOutMessage> outgoing{kQueue}; ///< owner -> link thread
  /// Owner fills back(), then publish(); the link encodes and sends each published image once.
  core::TripleBuffer<IgtlImage>& image(std::size_t stream) { return *images_[stream]; }

  std::uint64_t receivedCount() const noexcept { return received_.load(); }  ///< decoded messages
  std::uint64_t sentCount() const noexcept { return sent_.load(); }          ///< messages written to a peer
  std::uint64_t droppedCount() const noexcept { return dropped_.load(); }    ///< all reasons
  DropReason lastDrop() const noexcept { return static_cast<DropReason>(last_drop_.load()); }
  std::uint64_t dropped(DropReason reason) const noexcept { return by_reason_[static_cast<std::size_t>(reason)].load(); }
  std::uint64_t connections() const noexcept { return connections_.load(); }  ///< peers served so far
  std::uint64_t losses() const noexcept { return losses_.load(); }            ///< of those, gone again
  bool connected() const noexcept { return connected_.load(); }

 private:
  enum class Stage { Header, Body, Skip };
  void run() noexcept;
  void serve(FileDescriptor fd) noexcept;
  bool receive(int fd) noexcept;  // false: close the connection
  bool send(int fd) noexcept;     // false: close the connection
  void discardOutgoing() noexcept;
  void drop(DropReason reason) noexcept;

  IgtlLinkOptions options_;
  std::unique_ptr<TcpListener> listener_;
  Endpoint peer_;
  std::uint16_t local_port_ = 0;
  std::vector<std::unique_ptr<core::TripleBuffer<IgtlImage>>> images_;
  std::vector<std::uint8_t> image_bytes_;  // one encoded IMAGE of the largest size, allocated once
  // receive state (link thread only)
  Stage stage_ = Stage::Header;
  std::array<std::uint8_t, igtl::kHeaderSize> header_bytes_{};
  std::size_t have_ = 0;       // bytes of the current header or body received
  std::uint64_t skip_ = 0;     // bytes of an oversized body still to skip
  igtl::Header header_;
  std::vector<std::uint8_t> body_;  // max_body bytes, allocated once
  igtl::Message message_;
  bool heard_ = false;  // bytes came in this pass

  std::atomic<std::uint64_t> received_{0}, sent_{0}, dropped_{0}, connections_{0}, losses_{0};
  std::array<std::atomic<std::uint64_t>, kDropReasons> by_reason_{};
  std::atomic<std::uint8_t> last_drop_{0};
  std::atomic<bool> connected_{false};
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace cobra::bridges
