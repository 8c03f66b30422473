#pragma once
/// @file
/// Byte-level building blocks of cobra's network protocols: little-endian fields written and read
/// one byte at a time (no struct memcpy, so no padding or host byte order leaks onto the wire),
/// CRC-32 (IEEE 802.3, the zlib/PNG one), the common 24-byte frame header and its 4-byte CRC
/// trailer, and the status every decoder returns. Everything here is noexcept and allocation-free.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace cobra::bridges::wire {

/// Why a frame was accepted or rejected. Decoders return it; receivers count rejections per value.
enum class DecodeStatus : std::uint8_t {
  Ok = 0,
  Truncated,        ///< fewer bytes than the header, or than header + payload_length + CRC
  BadMagic,         ///< the first four bytes are not the protocol's magic
  BadVersion,       ///< a protocol version this code does not speak
  BadType,          ///< unknown message type, or a type not expected in this direction
  BadLength,        ///< payload_length does not fit the type, or bytes follow the frame
  BadCrc,           ///< the CRC-32 trailer does not match
  NonFinite,        ///< a NaN or infinite number in the payload
  BadValue,         ///< a field out of its documented range (non-unit quaternion, reserved bits, ...)
  Late,             ///< sequence number not newer than the last accepted one
  Delayed,          ///< sender timestamp older than allowed (see LatenessFilter)
  WrongJointCount,  ///< joint count differs from what the receiver was configured for
  WrongToolCount,   ///< tool count differs from what the receiver was configured for
};
/// Number of DecodeStatus values (array sizes for per-reason counters).
inline constexpr std::size_t kDecodeStatusCount = 13;

/// "ok", "truncated", "bad_magic", ... (stable names, used by counters and the components' operations).
std::string_view toString(DecodeStatus status) noexcept;
/// The status named `name` (as toString); false when there is none.
bool parseDecodeStatus(std::string_view name, DecodeStatus& out) noexcept;

/// CRC-32 (reflected polynomial 0xEDB88320, initial value and final xor 0xFFFFFFFF).
std::uint32_t crc32(std::span<const std::uint8_t> bytes) noexcept;

/// Frame layout shared by every cobra protocol, all fields little-endian:
/// | offset | size | field                                             |
/// | 0      | 4    | magic (protocol-specific)                         |
/// | 4      | 2    | version                                           |
/// | 6      | 2    | message type                                      |
/// | 8      | 4    | sequence number (per sender, +1 per frame, wraps) |
/// | 12     | 8    | sender timestamp, ns, sender's monotonic clock    |
/// | 20     | 4    | payload_length (bytes)                            |
/// | 24     | n    | payload                                           |
/// | 24 + n | 4    | CRC-32 of bytes [0, 24 + n)                       |
inline constexpr std::size_t kHeaderSize = 24;
inline constexpr std::size_t kTrailerSize = 4;

struct FrameHeader {
  std::uint32_t magic = 0;
  std::uint16_t version = 0;
  std::uint16_t type = 0;
  std::uint32_t sequence = 0;
  std::uint64_t timestamp_ns = 0;
  std::uint32_t payload_length = 0;
};

/// Writes little-endian fields into a fixed buffer; `ok()` turns false (and nothing more is
/// written) when the buffer is too small.
class Writer {
 public:
  explicit Writer(std::span<std::uint8_t> out) noexcept : out_(out) {}
  void u16(std::uint16_t v) noexcept { bytes(v, 2); }
  void u32(std::uint32_t v) noexcept { bytes(v, 4); }
  void u64(std::uint64_t v) noexcept { bytes(v, 8); }
  void f64(double v) noexcept;
  std::size_t size() const noexcept { return pos_; }
  bool ok() const noexcept { return ok_; }
  /// Overwrites 4 bytes at `offset` (already written), e.g. a length known only at the end.
  void patchU32(std::size_t offset, std::uint32_t v) noexcept;

 private:
  void bytes(std::uint64_t v, std::size_t n) noexcept;
  std::span<std::uint8_t> out_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

/// Reads little-endian fields; `ok()` turns false (reads give 0) past the end.
class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> in) noexcept : in_(in) {}
  std::uint16_t u16() noexcept { return static_cast<std::uint16_t>(bytes(2)); }
  std::uint32_t u32() noexcept { return static_cast<std::uint32_t>(bytes(4)); }
  std::uint64_t u64() noexcept { return bytes(8); }
  double f64() noexcept;
  std::size_t position() const noexcept { return pos_; }
  bool ok() const noexcept { return ok_; }

 private:
  std::uint64_t bytes(std::size_t n) noexcept;
  std::span<const std::uint8_t> in_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

/// Writes header + payload (given by `payload`, called with a Writer positioned after the header)
/// + CRC into `out`. Returns the frame size, or 0 when `out` is too small.
template <class PayloadWriter>
std::size_t writeFrame(std::span<std::uint8_t> out, const FrameHeader& header, PayloadWriter&& payload) noexcept {
  Writer w(out);
  w.u32(header.magic);
  w.u16(header.version);
  w.u16(header.type);
  w.u32(header.sequence);
  w.u64(header.timestamp_ns);
  w.u32(0);
  payload(w);
  if (!w.ok()) return 0;
  const std::size_t payload_length = w.size() - kHeaderSize;
  w.patchU32(20, static_cast<std::uint32_t>(payload_length));
  w.u32(crc32(out.first(w.size())));
  return w.ok() ? w.size() : 0;
}

/// Checks the header of `bytes` (magic, version, and that payload_length <= max_payload) without
/// needing the whole frame. On Ok, `header` is filled and `frame_size` = 24 + payload_length + 4.
/// Truncated when fewer than 24 bytes are given. Stream receivers use it to find frame boundaries.
DecodeStatus peekHeader(std::span<const std::uint8_t> bytes, std::uint32_t magic, std::uint16_t version,
                        std::size_t max_payload, FrameHeader& header, std::size_t& frame_size) noexcept;

/// Checks a whole frame: peekHeader, then that `bytes` holds exactly the frame (Truncated when
/// shorter, BadLength when longer), then the CRC. On Ok, `payload` views the payload bytes.
DecodeStatus checkFrame(std::span<const std::uint8_t> bytes, std::uint32_t magic, std::uint16_t version,
                        std::size_t max_payload, FrameHeader& header, std::span<const std::uint8_t>& payload) noexcept;

/// Rejects frames that arrive out of order or too late. Sequence numbers compare with serial
/// arithmetic (RFC 1982: newer when (s - last) mod 2^32 is in [1, 2^31)). Timestamps come from the
/// sender's clock, which need not be ours: the filter tracks the smallest (arrival - sent) seen,
/// i.e. clock offset + the fastest transit, and rejects a frame whose (arrival - sent) exceeds it
/// by more than `max_delay_ns` (it sat in a queue or the network that long). `reset` forgets the
/// history (a new connection, or a sender that restarted its sequence numbers).
class LatenessFilter {
 public:
  /// `max_delay_ns` <= 0 disables the timestamp check.
  explicit LatenessFilter(std::int64_t max_delay_ns = 0) noexcept : max_delay_ns_(max_delay_ns) {}
  void setMaxDelay(std::int64_t max_delay_ns) noexcept { max_delay_ns_ = max_delay_ns; }
  /// Ok (and the frame becomes the last accepted), Late or Delayed. `arrival_ns`: receiver's clock.
  DecodeStatus accept(std::uint32_t sequence, std::uint64_t sender_ns, std::int64_t arrival_ns) noexcept;
  void reset() noexcept { has_last_ = false; }

 private:
  std::int64_t max_delay_ns_;
  bool has_last_ = false;
  std::uint32_t last_sequence_ = 0;
  std::int64_t min_offset_ns_ = 0;
};

/// True when every value is finite.
bool allFinite(std::span<const double> values) noexcept;

}  // namespace cobra::bridges::wire
