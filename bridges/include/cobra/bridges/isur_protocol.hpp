#pragma once
/// @file
/// cobra's UDP protocol between the I-SUR robot controller and the local I-SUR server (thesis
/// §4.5.7), version 2: robots with 1..kMaxTools tools (the puncturing robot: 1, the needle; the
/// suturing robot of §5.3: 2, tool 0 the Endo Stitch on the 4-DOF arm, tool 1 the gripper's stick on
/// the 6-DOF arm). One frame per datagram, in the common layout of wire.hpp with magic "ISUR"
/// (bytes 49 53 55 52, i.e. 0x52555349 read little-endian) and version 2. Payloads (little-endian):
///
/// type 1, JointCommand (server -> controller), 8 + 8n bytes:
///   u16 n (1..16 joints) | u16 reserved = 0 | u32 reserved = 0 | n x f64 desired joint positions (rad / m)
/// type 2, CartesianCommand (server -> controller), 8 + 56m bytes:
///   u16 m (1..kMaxTools tools) | u16 mask (bit t: pose t is a new target for tool t; a clear bit: tool
///   t keeps its current target; at least one bit, none at or above m) | u32 reserved = 0 |
///   m x 7 f64 desired tool poses: x, y, z (m), qx, qy, qz, qw (unit quaternion: ||q| - 1| <= kQuatTolerance,
///   checked for every tool, masked or not)
/// type 3, State (controller -> server), 16 + 8n + 104m bytes:
///   u16 n (1..16) | u16 flags (StateFlag) | u16 m (1..kMaxTools) | u16 reserved = 0 |
///   u32 completed Endo Stitch actuations since the controller started | u32 the last ToolActuation
///   request handled (0: none yet) | n x f64 measured joints (rad / m) |
///   m x (7 f64 measured tool pose (as above) | 6 f64 wrench of the tool's F/T sensor: fx, fy, fz (N),
///   tx, ty, tz (N·m), sensor frame)
/// type 4, ToolActuation (server -> controller), 8 bytes:
///   u16 tool (0..kMaxTools-1) | u16 reserved = 0 | u32 request (>= 1; the controller handles each
///   request number once, so the server may repeat it until a state acknowledges it)
///
/// Version 1 (one tool, no actuation) is not accepted (BadVersion): the two ends of the link are
/// cobra's server and a controller speaking this protocol, upgraded together; a version 1 peer
/// could not read the version 2 frames sent back anyway, so half a link would only hide the
/// mismatch, which the bad_version counter shows at once.
///
/// Decoders never throw or allocate; a frame of the wrong direction is BadType.

#include <array>
#include <cstdint>
#include <span>

#include "cobra/bridges/wire.hpp"

namespace cobra::bridges::isur {

inline constexpr std::uint32_t kMagic = 0x52555349U;  // "ISUR"
inline constexpr std::uint16_t kVersion = 2;
inline constexpr std::uint16_t kMaxJoints = 16;
/// Tools per robot: the two-armed suturing I-SUR has two; a third would need another arm.
inline constexpr std::uint16_t kMaxTools = 2;
/// | |q| - 1 | allowed for a transmitted quaternion (it is renormalised after the check).
inline constexpr double kQuatTolerance = 1e-6;
/// Payload bytes of a State before the joints, and per tool.
inline constexpr std::size_t kStatePrefix = 16;
inline constexpr std::size_t kStateBytesPerTool = 8 * (7 + 6);
/// Largest payload and frame of this protocol (a State with 16 joints and kMaxTools tools), bytes.
inline constexpr std::size_t kMaxPayload = kStatePrefix + 8 * kMaxJoints + kStateBytesPerTool * kMaxTools;
inline constexpr std::size_t kMaxFrameSize = wire::kHeaderSize + kMaxPayload + wire::kTrailerSize;

enum class MessageType : std::uint16_t { JointCommand = 1, CartesianCommand = 2, State = 3, ToolActuation = 4 };

/// A pose: position (m) and unit quaternion (x, y, z, w).
struct Pose {
  std::array<double, 3> position{};
  std::array<double, 4> quaternion{0.0, 0.0, 0.0, 1.0};
};

enum StateFlag : std::uint16_t {
  kWrenchSaturated = 1U << 0,  ///< tool 0's F/T sensor saturated
  kPoseValid = 1U << 1,        ///< the tool poses are valid (forward kinematics succeeded)
  kCartesianHeld = 1U << 2,    ///< the last Cartesian command was refused: the robot holds
  kCartesianDiscontinuous = 1U << 3,  ///< with kCartesianHeld: refused by the continuity rule
  kWrenchSaturatedTool1 = 1U << 4,    ///< tool 1's F/T sensor saturated (only with m = 2)
  kActuating = 1U << 5,               ///< an Endo Stitch actuation is in progress
  kActuationRefused = 1U << 6,        ///< the acknowledged request was refused (busy, or no actuator)
};
inline constexpr std::uint16_t kKnownStateFlags = 0x7F;

/// The kWrenchSaturated bit of tool `tool` (0 or 1).
constexpr std::uint16_t wrenchSaturatedFlag(std::size_t tool) noexcept {
  return tool == 0 ? kWrenchSaturated : kWrenchSaturatedTool1;
}

/// A request to actuate a tool (the Endo Stitch: pass the needle from one jaw to the other).
struct Actuation {
  std::uint16_t tool = 0;     ///< 0-based tool index
  std::uint32_t request = 0;  ///< >= 1, a new number per request
};

/// A command to the controller: joints, Cartesian poses or a tool actuation.
struct Command {
  MessageType type = MessageType::JointCommand;
  std::uint16_t joint_count = 0;            ///< JointCommand
  std::array<double, kMaxJoints> joints{};  ///< JointCommand: rad / m, first joint_count used
  std::uint16_t tool_count = 1;             ///< CartesianCommand: m
  std::uint16_t tool_mask = 1;              ///< CartesianCommand: bit t, poses[t] is a new target
  std::array<Pose, kMaxTools> poses;        ///< CartesianCommand: first tool_count used
  Actuation actuation;                      ///< ToolActuation
};

/// What the controller measured at one tool.
struct ToolState {
  Pose pose;
  std::array<double, 6> wrench{};  ///< fx, fy, fz (N), tx, ty, tz (N·m), sensor frame
};

/// What the controller measured.
struct State {
  std::uint16_t joint_count = 0;
  std::uint16_t flags = 0;                  ///< StateFlag bits
  std::uint16_t tool_count = 1;             ///< m
  std::uint32_t actuations = 0;             ///< completed Endo Stitch actuations since the controller started
  std::uint32_t actuation_request = 0;      ///< last ToolActuation request handled (0: none)
  std::array<double, kMaxJoints> joints{};  ///< rad / m, first joint_count used
  std::array<ToolState, kMaxTools> tools;   ///< first tool_count used
};

/// Frame header fields a sender chooses.
struct Stamp {
  std::uint32_t sequence = 0;
  std::uint64_t timestamp_ns = 0;
};

/// Encodes into `out` (>= kMaxFrameSize is always enough). Returns the frame size, 0 when `out` is
/// too small or the message is not encodable (joint count outside 1..16, tool count outside
/// 1..kMaxTools, a mask with no tool or a bit at or above the tool count, an actuation of tool >=
/// kMaxTools or request 0, unknown type or flags).
std::size_t encode(const Command& command, const Stamp& stamp, std::span<std::uint8_t> out) noexcept;
std::size_t encode(const State& state, const Stamp& stamp, std::span<std::uint8_t> out) noexcept;

/// Decodes one datagram holding a command. `out` and `header` are written only on Ok.
wire::DecodeStatus decode(std::span<const std::uint8_t> datagram, Command& out, wire::FrameHeader& header) noexcept;
/// Decodes one datagram holding a state. `out` and `header` are written only on Ok.
wire::DecodeStatus decode(std::span<const std::uint8_t> datagram, State& out, wire::FrameHeader& header) noexcept;

}  // namespace cobra::bridges::isur
