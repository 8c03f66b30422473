#pragma once
/// @file
/// Splits a TCP byte stream into frames of the common layout (wire.hpp): bytes are appended as
/// they arrive, complete frames come out one at a time. Fixed buffer, no allocation.

#include <array>
#include <cstdint>
#include <cstring>
#include <span>

#include "cobra/bridges/wire.hpp"

namespace cobra::bridges {

class StreamFramer {
 public:
  static constexpr std::size_t kCapacity = 4096;

  StreamFramer(std::uint32_t magic, std::uint16_t version, std::size_t max_payload) noexcept
      : magic_(magic), version_(version), max_payload_(max_payload) {}

  /// Free space to receive into; call `commit` with the number of bytes written there.
  std::span<std::uint8_t> space() noexcept { return std::span<std::uint8_t>(buffer_).subspan(fill_); }
  void commit(std::size_t n) noexcept { fill_ += n; }

  enum class Next { Frame, NeedMore, Broken };
  /// Frame: `frame` views the next complete frame (valid until the next call); NeedMore: wait for
  /// bytes; Broken: the header at the front is invalid (`why`): the frame boundaries are lost and
  /// the connection must be dropped.
  Next next(std::span<const std::uint8_t>& frame, wire::DecodeStatus& why) noexcept {
    if (consumed_ > 0) {
      std::memmove(buffer_.data(), buffer_.data() + consumed_, fill_ - consumed_);
      fill_ -= consumed_;
      consumed_ = 0;
    }
    wire::FrameHeader header;
    std::size_t size = 0;
    const auto have = std::span<const std::uint8_t>(buffer_.data(), fill_);
    why = wire::peekHeader(have, magic_, version_, max_payload_, header, size);
    if (why == wire::DecodeStatus::Truncated) return Next::NeedMore;
    if (why != wire::DecodeStatus::Ok) return Next::Broken;
    if (fill_ < size) return Next::NeedMore;
    frame = have.first(size);
    consumed_ = size;
    return Next::Frame;
  }

  void clear() noexcept { fill_ = consumed_ = 0; }

 private:
  std::uint32_t magic_;
  std::uint16_t version_;
  std::size_t max_payload_;
  std::array<std::uint8_t, kCapacity> buffer_{};
  std::size_t fill_ = 0;
  std::size_t consumed_ = 0;
};

}  // namespace cobra::bridges
