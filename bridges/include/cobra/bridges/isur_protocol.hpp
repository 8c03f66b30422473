#pragma once
/// @file
/// cobra's UDP protocol between the I-SUR robot controller and the local I-SUR server (thesis
/// §4.5.7). One frame per datagram, in the common layout of wire.hpp with magic "ISUR"
/// (bytes 49 53 55 52, i.e. 0x52555349 read little-endian) and version 1. Payloads (little-endian):
///
/// type 1, JointCommand (server -> controller), 8 + 8n bytes:
///   u16 n (1..16 joints) | u16 reserved = 0 | u32 reserved = 0 | n x f64 desired joint positions (rad / m)
/// type 2, CartesianCommand (server -> controller), 56 bytes:
///   7 x f64 desired tool pose: x, y, z (m), qx, qy, qz, qw (unit quaternion: ||q| - 1| <= kQuatTolerance)
/// type 3, State (controller -> server), 112 + 8n bytes:
///   u16 n (1..16) | u16 flags (bit 0 wrench saturated, bit 1 pose valid, bit 2 Cartesian command held,
///   bit 3 it was held because it was not continuous (kinematics::ContinuousIk: another IK branch,
///   or a joint step above max velocity x period), others 0) | u32 reserved = 0 |
///   n x f64 measured joints (rad / m) | 7 x f64 measured tool pose
///   (as above) | 6 x f64 wrench of the wrist F/T sensor (AtiNano17): fx, fy, fz (N), tx, ty, tz (N·m)
///
/// Decoders never throw or allocate; a frame of the wrong direction is BadType.

#include <array>
#include <cstdint>
#include <span>

#include "cobra/bridges/wire.hpp"

namespace cobra::bridges::isur {

inline constexpr std::uint32_t kMagic = 0x52555349U;  // "ISUR"
inline constexpr std::uint16_t kVersion = 1;
inline constexpr std::uint16_t kMaxJoints = 16;
/// | |q| - 1 | allowed for a transmitted quaternion (it is renormalised after the check).
inline constexpr double kQuatTolerance = 1e-6;
/// Largest frame of this protocol (a State with 16 joints), bytes.
inline constexpr std::size_t kMaxFrameSize = wire::kHeaderSize + 112 + 8 * kMaxJoints + wire::kTrailerSize;
inline constexpr std::size_t kMaxPayload = 112 + 8 * kMaxJoints;

enum class MessageType : std::uint16_t { JointCommand = 1, CartesianCommand = 2, State = 3 };

/// A pose: position (m) and unit quaternion (x, y, z, w).
struct Pose {
  std::array<double, 3> position{};
  std::array<double, 4> quaternion{0.0, 0.0, 0.0, 1.0};
};

enum StateFlag : std::uint16_t {
  kWrenchSaturated = 1U << 0,
  kPoseValid = 1U << 1,
  kCartesianHeld = 1U << 2,
  kCartesianDiscontinuous = 1U << 3,  ///< with kCartesianHeld: refused by the continuity rule
};
inline constexpr std::uint16_t kKnownStateFlags = 0xF;

/// A command to the controller: joints or a Cartesian pose.
struct Command {
  MessageType type = MessageType::JointCommand;  ///< JointCommand or CartesianCommand
  std::uint16_t joint_count = 0;                 ///< used by JointCommand
  std::array<double, kMaxJoints> joints{};       ///< rad / m, first joint_count used
  Pose pose;                                     ///< used by CartesianCommand
};

/// What the controller measured.
struct State {
  std::uint16_t joint_count = 0;
  std::uint16_t flags = 0;                  ///< StateFlag bits
  std::array<double, kMaxJoints> joints{};  ///< rad / m, first joint_count used
  Pose pose;
  std::array<double, 6> wrench{};  ///< fx, fy, fz (N), tx, ty, tz (N·m), sensor frame
};

/// Frame header fields a sender chooses.
struct Stamp {
  std::uint32_t sequence = 0;
  std::uint64_t timestamp_ns = 0;
};

/// Encodes into `out` (>= kMaxFrameSize is always enough). Returns the frame size, 0 when `out` is
/// too small or the message is not encodable (joint count outside 1..16, wrong type).
std::size_t encode(const Command& command, const Stamp& stamp, std::span<std::uint8_t> out) noexcept;
std::size_t encode(const State& state, const Stamp& stamp, std::span<std::uint8_t> out) noexcept;

/// Decodes one datagram holding a command. `out` and `header` are written only on Ok.
wire::DecodeStatus decode(std::span<const std::uint8_t> datagram, Command& out, wire::FrameHeader& header) noexcept;
/// Decodes one datagram holding a state. `out` and `header` are written only on Ok.
wire::DecodeStatus decode(std::span<const std::uint8_t> datagram, State& out, wire::FrameHeader& header) noexcept;

}  // namespace cobra::bridges::isur
