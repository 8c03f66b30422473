#pragma once
/// @file
/// cobra's TCP protocol between the Omni application (the stand-alone program that drives the
/// Phantom Omni, thesis §4.5.9) and the OmniPhantomBridge. A byte stream of frames in the common
/// layout of wire.hpp with magic "OMNI" (bytes 4F 4D 4E 49, 0x494E4D4F read little-endian) and
/// version 1. Payloads (little-endian):
///
/// type 1, State (application -> bridge), 112 bytes:
///   7 x f64 stylus pose: x, y, z (m), qx, qy, qz, qw (unit quaternion) | 6 x f64 twist: vx, vy, vz
///   (m/s), wx, wy, wz (rad/s) | u32 buttons (bit 0 first stylus button, bit 1 second, others 0) |
///   u32 reserved = 0
/// type 2, WrenchCommand (bridge -> application), 48 bytes:
///   6 x f64 wrench to render: fx, fy, fz (N), tx, ty, tz (N·m), device base frame
///
/// A stream receiver reads the 24-byte header first (wire::peekHeader gives the frame size), then
/// the rest; a header that fails (bad magic/version/length) leaves no way to find the next frame,
/// so the connection is dropped.

#include <array>
#include <cstdint>
#include <span>

#include "cobra/bridges/wire.hpp"

namespace cobra::bridges::omni {

inline constexpr std::uint32_t kMagic = 0x494E4D4FU;  // "OMNI"
inline constexpr std::uint16_t kVersion = 1;
inline constexpr std::size_t kStatePayload = 112;
inline constexpr std::size_t kWrenchPayload = 48;
inline constexpr std::size_t kMaxPayload = kStatePayload;
inline constexpr std::size_t kMaxFrameSize = wire::kHeaderSize + kMaxPayload + wire::kTrailerSize;
inline constexpr std::uint32_t kKnownButtons = 0x3;
inline constexpr double kQuatTolerance = 1e-6;

enum class MessageType : std::uint16_t { State = 1, WrenchCommand = 2 };

struct State {
  std::array<double, 3> position{};                    ///< m
  std::array<double, 4> quaternion{0.0, 0.0, 0.0, 1.0};  ///< x, y, z, w
  std::array<double, 6> twist{};                       ///< m/s, rad/s
  std::uint32_t buttons = 0;                           ///< bit 0, bit 1: stylus buttons
};

struct WrenchCommand {
  std::array<double, 6> wrench{};  ///< N, N·m
};

struct Stamp {
  std::uint32_t sequence = 0;
  std::uint64_t timestamp_ns = 0;
};

/// Encodes into `out`; returns the frame size or 0 when `out` is too small.
std::size_t encode(const State& state, const Stamp& stamp, std::span<std::uint8_t> out) noexcept;
std::size_t encode(const WrenchCommand& command, const Stamp& stamp, std::span<std::uint8_t> out) noexcept;

/// Decodes exactly one frame. `out` and `header` are written only on Ok.
wire::DecodeStatus decode(std::span<const std::uint8_t> frame, State& out, wire::FrameHeader& header) noexcept;
wire::DecodeStatus decode(std::span<const std::uint8_t> frame, WrenchCommand& out, wire::FrameHeader& header) noexcept;

}  // namespace cobra::bridges::omni
